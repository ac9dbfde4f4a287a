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

/// Three faces of a 40 cm cube (x = 0, y = 0, z = 0 planes, 0..0.4 m) sampled every 5 mm: a
/// shape that pins all six degrees of freedom.
std::vector<Eigen::Vector3d> cube_corner() {
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i <= 80; ++i) {
        for (int j = 0; j <= 80; ++j) {
            const double a = 0.005 * i, b = 0.005 * j;
            points.emplace_back(0.0, a, b);
            points.emplace_back(a, 0.0, b);
            points.emplace_back(a, b, 0.0);
        }
    }
    return points;
}

TEST(Registration, RecoversTheMisplacementOfAPartialModelWithOutliers) {
    const auto gt = cube_corner();
    // The reconstruction: every other point of two of the faces (a partial view), plus 200
    // points of a floor 10 cm below that the ground truth does not have, the whole misplaced by
    // 1.5 cm and 2 degrees (as a wrong first object pose places a model).
    std::vector<Eigen::Vector3d> model;
    for (size_t i = 0; i < gt.size(); i += 2) {
        if (gt[i].z() != 0.0 || gt[i].x() == 0.0 || gt[i].y() == 0.0) model.push_back(gt[i]);
    }
    for (int i = 0; i < 200; ++i) model.emplace_back(0.002 * i, 0.2, -0.10);
    const Eigen::Isometry3d misplaced =
        test::make_transform(2.0 * M_PI / 180.0, Eigen::Vector3d(1, 2, 3),
                             Eigen::Vector3d(0.012, -0.010, 0.008));
    const auto est = transform_points(misplaced, model);

    ReconstructionConfig one_cm;
    one_cm.threshold_m = 0.01;
    auto before = score_reconstruction(gt, est, one_cm);
    ASSERT_TRUE(before);
    EXPECT_LT(before->accuracy, 0.7);

    auto fit = register_reconstruction(gt, est, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(fit) << fit.status().to_string();
    const Eigen::Isometry3d error = fit->gt_T_est * misplaced;  // identity when recovered
    EXPECT_LT(error.translation().norm(), 1e-3);
    EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 0.05 * M_PI / 180.0);
    EXPECT_NEAR(fit->correction_rotation_deg, 2.0, 0.05);
    // How far the fit moved the model's centre (that of its bounding box).
    Eigen::Vector3d lo = est.front(), hi = est.front();
    for (const auto& p : est) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    EXPECT_NEAR(fit->correction_translation_m, (misplaced.inverse() * centre - centre).norm(),
                1e-3);
    EXPECT_LT(fit->rmse_m, 0.002);

    auto after = score_reconstruction(gt, transform_points(fit->gt_T_est, est), one_cm);
    ASSERT_TRUE(after);
    // All but the floor (200 of the points) lie on the cube again.
    EXPECT_NEAR(after->accuracy, 1.0 - 200.0 / static_cast<double>(est.size()), 1e-9);
}

TEST(Registration, AModelNowhereNearTheGroundTruthIsAnErrorNotAFit) {
    const auto gt = cube_corner();
    const auto far = shifted(gt, {1.0, 0, 0});
    auto fit = register_reconstruction(gt, far, Eigen::Isometry3d::Identity());
    ASSERT_FALSE(fit);
    EXPECT_NE(fit.status().message().find("within"), std::string::npos)
        << fit.status().to_string();
    EXPECT_FALSE(register_reconstruction({}, gt, Eigen::Isometry3d::Identity()));
    RegistrationConfig bad;
    bad.max_distance_m = 0;
    EXPECT_FALSE(register_reconstruction(gt, gt, Eigen::Isometry3d::Identity(), bad));
}

}  // namespace
}  // namespace df::eval
