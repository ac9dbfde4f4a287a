// ATE, stamp association and object trajectories on trajectories whose answer is known.
#include <gtest/gtest.h>

#include "eval/trajectory_metrics.hpp"
#include "eval_test_support.hpp"

namespace df::eval {
namespace {

using test::make_transform;
using test::smooth_trajectory;
using test::transformed;

TEST(Ate, TrajectoryAgainstItselfIsZero) {
    const Trajectory gt = smooth_trajectory(100.0, 30.0, 300);
    auto ate = compute_ate(gt, gt);
    ASSERT_TRUE(ate) << ate.status().to_string();
    EXPECT_EQ(ate->translation_m.count, 300u);
    EXPECT_LT(ate->translation_m.rmse, 1e-12);
    EXPECT_LT(ate->translation_m.max, 1e-12);
    EXPECT_TRUE(ate->gt_T_est.isApprox(Eigen::Isometry3d::Identity(), 1e-12));
}

TEST(Ate, RigidlyMovedCopyAlignsToZeroAndRecoversTheTransform) {
    const Trajectory gt = smooth_trajectory(0.0, 30.0, 300);
    // The estimate lives in another world frame: est_world_T_gt_world applied to every pose.
    const Eigen::Isometry3d est_T_gt =
        make_transform(0.7, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1.0, -2.0, 0.5));
    Trajectory est;
    for (const auto& p : gt) est.push_back(transformed(est_T_gt, p));
    auto ate = compute_ate(gt, est);
    ASSERT_TRUE(ate) << ate.status().to_string();
    EXPECT_LT(ate->translation_m.rmse, 1e-9);
    EXPECT_LT((ate->gt_T_est.matrix() - est_T_gt.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Ate, NoiseThatNoRigidMotionExplainsGivesItsRms) {
    const Trajectory gt = smooth_trajectory(0.0, 30.0, 200);
    const size_t n = gt.size();
    // Noise s_i * d along a fixed direction, with s orthogonal to 1 and to each centred gt
    // coordinate: then the best alignment is the identity and the ATE is exactly RMS(s).
    Eigen::MatrixXd basis(n, 4);
    Eigen::VectorXd s(n);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : gt) mean += p.t / static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) {
        basis.row(static_cast<Eigen::Index>(i)) << 1.0, (gt[i].t - mean).transpose();
        s[static_cast<Eigen::Index>(i)] = 0.01 * static_cast<double>((i * 7) % 5) - 0.02 +
                                          0.003 * std::cos(static_cast<double>(i));
    }
    s -= basis * basis.colPivHouseholderQr().solve(s);  // project out the rigidly explainable
    const Eigen::Vector3d d = Eigen::Vector3d(1, -2, 2).normalized();
    Trajectory est = gt;
    for (size_t i = 0; i < n; ++i) est[i].t += s[static_cast<Eigen::Index>(i)] * d;
    const double expected_rmse = std::sqrt(s.squaredNorm() / static_cast<double>(n));
    ASSERT_GT(expected_rmse, 0.005);

    auto ate = compute_ate(gt, est);
    ASSERT_TRUE(ate) << ate.status().to_string();
    EXPECT_NEAR(ate->translation_m.rmse, expected_rmse, 1e-9);
    EXPECT_NEAR(ate->translation_m.max, s.cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(ate->translation_m.mean, s.cwiseAbs().mean(), 1e-9);
    EXPECT_TRUE(ate->gt_T_est.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
}

TEST(Association, GreedyByDifferenceOneToOneWithinMaxDifference) {
    const std::vector<double> gt = {1.00, 1.10, 1.20, 1.30};
    const std::vector<double> est = {1.005, 1.012, 1.13, 1.195, 1.2049, 1.40};
    const auto matches = associate_stamps(gt, est, {0.02, 0.0});
    // (1.20, 1.2049) is the closest pair, then (1.00, 1.005); 1.012 and 1.195 lose their gt
    // stamp to a closer estimate; 1.13 and 1.40 are farther than 0.02 s from any gt stamp.
    ASSERT_EQ(matches.size(), 2u);
    EXPECT_EQ(matches[0].gt, 0u);
    EXPECT_EQ(matches[0].est, 0u);
    EXPECT_EQ(matches[1].gt, 2u);
    EXPECT_EQ(matches[1].est, 4u);
}

TEST(Association, WiderWindowAdmitsMorePairs) {
    const std::vector<double> gt = {1.00, 1.10, 1.20, 1.30};
    const std::vector<double> est = {1.005, 1.012, 1.13, 1.195, 1.2049, 1.40};
    const auto matches = associate_stamps(gt, est, {0.05, 0.0});
    ASSERT_EQ(matches.size(), 3u);  // 1.10 takes 1.13 now; 1.30 is 0.095 from 1.195 and 1.40
    EXPECT_EQ(matches[1].gt, 1u);
    EXPECT_EQ(matches[1].est, 2u);
}

TEST(Ate, TimeOffsetAddedToTheEstimateStamps) {
    const Trajectory gt = smooth_trajectory(10.0, 10.0, 100);
    Trajectory est = gt;
    for (auto& p : est) p.stamp_s += 0.55;  // the estimate's clock runs 0.55 s ahead
    auto none = compute_ate(gt, est);
    ASSERT_FALSE(none);  // every est stamp is 0.05 s from the nearest gt stamp
    EXPECT_NE(none.status().message().find("no common stamps"), std::string::npos);
    auto ate = compute_ate(gt, est, {0.02, -0.55});
    ASSERT_TRUE(ate) << ate.status().to_string();
    EXPECT_EQ(ate->pairs.size(), 100u);
    EXPECT_LT(ate->translation_m.rmse, 1e-9);
}

TEST(Ate, NoCommonStampsNamesBothRanges) {
    const Trajectory gt = smooth_trajectory(0.0, 10.0, 11);
    const Trajectory est = smooth_trajectory(100.0, 10.0, 11);
    auto ate = compute_ate(gt, est);
    ASSERT_FALSE(ate);
    const std::string& m = ate.status().message();
    EXPECT_NE(m.find("[0.000000, 1.000000] s"), std::string::npos) << m;
    EXPECT_NE(m.find("[100.000000, 101.000000] s"), std::string::npos) << m;
}

TEST(ObjectTrajectory, FirstPoseAlignmentRemovesTheWorldFrameAndKeepsLaterErrors) {
    const Trajectory gt = smooth_trajectory(5.0, 30.0, 120);
    const Eigen::Isometry3d est_T_gt =
        make_transform(-1.2, Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(3, 0, -1));
    Trajectory est;
    for (const auto& p : gt) est.push_back(transformed(est_T_gt, p));
    auto exact = compute_object_errors(gt, est);
    ASSERT_TRUE(exact) << exact.status().to_string();
    EXPECT_EQ(exact->ate.alignment, AlignmentKind::kFirstPose);
    EXPECT_LT(exact->ate.translation_m.max, 1e-9);
    EXPECT_LT(exact->rotation_deg.max, 1e-6);
    EXPECT_LT((exact->ate.gt_T_est.matrix() - est_T_gt.inverse().matrix()).cwiseAbs().maxCoeff(),
              1e-9);

    // From pose 60 on, the estimate is 5 cm off in the ground-truth world: half the poses err
    // by exactly 0.05 m once the first pose is aligned (Horn would spread the error instead).
    const Eigen::Vector3d offset_gt_world(0, 0.03, 0.04);
    for (size_t i = 60; i < est.size(); ++i) {
        io::StampedPose moved = gt[i];
        moved.t += offset_gt_world;
        est[i] = transformed(est_T_gt, moved);
    }
    auto drift = compute_object_errors(gt, est);
    ASSERT_TRUE(drift) << drift.status().to_string();
    EXPECT_NEAR(drift->ate.translation_m.max, 0.05, 1e-9);
    EXPECT_NEAR(drift->ate.translation_m.median, 0.025, 1e-9);  // 60 zeros, 60 x 0.05
    EXPECT_NEAR(drift->ate.translation_m.rmse, 0.05 * std::sqrt(0.5), 1e-9);
    ASSERT_TRUE(drift->rpe.has_value()) << drift->rpe_error;
}

TEST(ObjectTrajectory, AlignsTheFirstAssociatedPose) {
    const Trajectory gt = smooth_trajectory(0.0, 30.0, 90);
    const Eigen::Isometry3d est_T_gt =
        make_transform(0.4, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0));
    Trajectory est;  // the object is first seen at frame 30
    for (size_t i = 30; i < gt.size(); ++i) est.push_back(transformed(est_T_gt, gt[i]));
    auto object = compute_object_errors(gt, est);
    ASSERT_TRUE(object) << object.status().to_string();
    EXPECT_EQ(object->ate.pairs.size(), 60u);
    EXPECT_DOUBLE_EQ(object->ate.pairs.front().gt_stamp_s, gt[30].stamp_s);
    EXPECT_LT(object->ate.translation_m.max, 1e-9);
}

}  // namespace
}  // namespace df::eval
