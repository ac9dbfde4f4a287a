// Reconstruction accuracy/completeness (PLY reading is tested in tests/unit/io_ply).
#include "eval/reconstruction.hpp"

#include <gtest/gtest.h>

#include "eval_test_support.hpp"

namespace df::eval {
namespace {

/// A 1 m x 1 m plane z = 0 sampled every 1 cm (101 x 101 points).
std::vector<Eigen::Vector3d> plane_model() {
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i <= 100; ++i) {
        for (int j = 0; j <= 100; ++j) points.emplace_back(0.01 * i, 0.01 * j, 0.0);
    }
    return points;
}

std::vector<Eigen::Vector3d> shifted(std::vector<Eigen::Vector3d> points,
                                     const Eigen::Vector3d& d) {
    for (auto& p : points) p += d;
    return points;
}

TEST(Reconstruction, ModelAgainstItselfIsPerfect) {
    const auto model = plane_model();
    auto r = score_reconstruction(model, model);
    ASSERT_TRUE(r) << r.status().to_string();
    EXPECT_DOUBLE_EQ(r->accuracy, 1.0);
    EXPECT_DOUBLE_EQ(r->completeness, 1.0);
    EXPECT_DOUBLE_EQ(r->est_to_gt_m.max, 0.0);
    EXPECT_EQ(r->gt_points, 10201u);
}

TEST(Reconstruction, ShiftBeyondThresholdScoresZeroAndWithinScoresOne) {
    const auto model = plane_model();
    ReconstructionConfig config;
    config.threshold_m = 0.02;
    auto far = score_reconstruction(model, shifted(model, {0, 0, 0.03}), config);
    ASSERT_TRUE(far);
    EXPECT_DOUBLE_EQ(far->accuracy, 0.0);
    EXPECT_DOUBLE_EQ(far->completeness, 0.0);
    EXPECT_NEAR(far->est_to_gt_m.mean, 0.03, 1e-12);
    auto near = score_reconstruction(model, shifted(model, {0, 0, 0.015}), config);
    ASSERT_TRUE(near);
    EXPECT_DOUBLE_EQ(near->accuracy, 1.0);
    EXPECT_DOUBLE_EQ(near->completeness, 1.0);
    EXPECT_NEAR(near->gt_to_est_m.median, 0.015, 1e-12);
}

TEST(Reconstruction, HandComputedPartialCase) {
    const std::vector<Eigen::Vector3d> gt = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    const std::vector<Eigen::Vector3d> est = {{0, 0, 0.005}, {1, 0, 0.03}, {10, 0, 0}};
    ReconstructionConfig config;
    config.threshold_m = 0.01;
    auto r = score_reconstruction(gt, est, config);
    ASSERT_TRUE(r);
    // est -> gt: 0.005, 0.03, 7; gt -> est: 0.005, 0.03, sqrt(1 + 0.03^2), sqrt(4 + 0.03^2).
    EXPECT_DOUBLE_EQ(r->accuracy, 1.0 / 3);
    EXPECT_DOUBLE_EQ(r->completeness, 1.0 / 4);
    EXPECT_NEAR(r->est_to_gt_m.mean, (0.005 + 0.03 + 7) / 3, 1e-12);
    EXPECT_NEAR(r->est_to_gt_m.median, 0.03, 1e-12);
    EXPECT_NEAR(r->gt_to_est_m.median, (0.03 + std::sqrt(1.0009)) / 2, 1e-12);
    EXPECT_NEAR(r->gt_to_est_m.mean, (0.005 + 0.03 + std::sqrt(1.0009) + std::sqrt(4.0009)) / 4,
                1e-12);
    EXPECT_NEAR(r->f_score, 2 * (1.0 / 3) * 0.25 / (1.0 / 3 + 0.25), 1e-12);
}

TEST(Reconstruction, TransformAppliedFirst) {
    const auto model = plane_model();
    const Eigen::Isometry3d est_T_gt =
        test::make_transform(0.5, Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(0.3, 0, 2));
    const auto est = transform_points(est_T_gt, model);
    auto raw = score_reconstruction(model, est);
    ASSERT_TRUE(raw);
    EXPECT_LT(raw->accuracy, 0.1);
    auto aligned = score_reconstruction(model, transform_points(est_T_gt.inverse(), est));
    ASSERT_TRUE(aligned);
    EXPECT_DOUBLE_EQ(aligned->accuracy, 1.0);
}

}  // namespace
}  // namespace df::eval
