// RPE on constant-velocity trajectories with a known drift.
#include <gtest/gtest.h>

#include "eval/trajectory_metrics.hpp"
#include "eval_test_support.hpp"

namespace df::eval {
namespace {

/// 10 s at 30 Hz (301 poses): position velocity_m_s * t, rotation yaw_rate_rad_s * t about z.
Trajectory constant_velocity(const Eigen::Vector3d& velocity_m_s, double yaw_rate_rad_s) {
    Trajectory t;
    for (int i = 0; i <= 300; ++i) {
        io::StampedPose p;
        p.stamp_s = 1000.0 + i / 30.0;
        const double since_start = i / 30.0;
        p.t = velocity_m_s * since_start;
        p.q = Eigen::Quaterniond(
            Eigen::AngleAxisd(yaw_rate_rad_s * since_start, Eigen::Vector3d::UnitZ()));
        t.push_back(p);
    }
    return t;
}

TEST(Rpe, TranslationDriftPerSecondAndPerFrame) {
    const Trajectory gt = constant_velocity({0.5, 0, 0}, 0.0);
    const Trajectory est = constant_velocity({0.55, 0, 0}, 0.0);  // 10 % too fast: 5 cm/s
    for (const RpeForm form : {RpeForm::kTumScript, RpeForm::kPaper}) {
        RpeConfig seconds;
        seconds.form = form;
        auto per_second = compute_rpe(gt, est, seconds);
        ASSERT_TRUE(per_second) << per_second.status().to_string();
        // Pairs (i, i + 30) for i = 0..269: TUM drops the pair ending at the last pose.
        EXPECT_EQ(per_second->pairs.size(), 270u);
        EXPECT_NEAR(per_second->translation_m.rmse, 0.05, 1e-9);
        EXPECT_NEAR(per_second->translation_m.max, 0.05, 1e-9);
        EXPECT_NEAR(per_second->translation_m.min, 0.05, 1e-9);
        EXPECT_LT(per_second->rotation_deg.max, 1e-9);

        RpeConfig frames;
        frames.unit = DeltaUnit::kFrames;
        frames.form = form;
        auto per_frame = compute_rpe(gt, est, frames);
        ASSERT_TRUE(per_frame) << per_frame.status().to_string();
        EXPECT_EQ(per_frame->pairs.size(), 299u);
        EXPECT_NEAR(per_frame->translation_m.median, 0.05 / 30, 1e-9);
    }
}

TEST(Rpe, RotationDriftPerSecond) {
    const Trajectory gt = constant_velocity({0, 0, 0}, 0.0);
    const Trajectory est = constant_velocity({0, 0, 0}, 2.0 / kDegPerRad);  // 2 deg/s yaw drift
    auto rpe = compute_rpe(gt, est);
    ASSERT_TRUE(rpe) << rpe.status().to_string();
    EXPECT_NEAR(rpe->rotation_deg.rmse, 2.0, 1e-9);
    EXPECT_NEAR(rpe->rotation_deg.min, 2.0, 1e-9);
    EXPECT_LT(rpe->translation_m.max, 1e-12);
}

TEST(Rpe, FormsDifferOnlyInTranslationWhenTheRotationIsWrong) {
    // Ground truth drives along x at 1 m/s; the estimate follows the same path but turns
    // 3 deg/s: its relative motion A = (Rz(3 deg), R_i^T v) against B = (I, v).
    const Trajectory gt = constant_velocity({1, 0, 0}, 0.0);
    const Trajectory est = constant_velocity({1, 0, 0}, 3.0 / kDegPerRad);
    RpeConfig tum, paper;
    paper.form = RpeForm::kPaper;
    auto a = compute_rpe(gt, est, tum);
    auto b = compute_rpe(gt, est, paper);
    ASSERT_TRUE(a && b);
    EXPECT_NEAR(a->rotation_deg.rmse, 3.0, 1e-9);
    EXPECT_NEAR(b->rotation_deg.rmse, 3.0, 1e-9);
    // Pair starting at t: t_A = Rz(-3t deg) v, t_B = v. Paper: |t_A - t_B|; TUM: |t_A - Rz(3) t_B|.
    const Eigen::Vector3d v(1, 0, 0);
    const RpePair& first = a->pairs[100];
    const double t0 = first.est_stamp_0_s - 1000.0;
    const Eigen::Vector3d t_a =
        Eigen::AngleAxisd(-3.0 * t0 / kDegPerRad, Eigen::Vector3d::UnitZ()) * v;
    const Eigen::Matrix3d rz3 =
        Eigen::AngleAxisd(3.0 / kDegPerRad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_NEAR(first.translation_m, (t_a - rz3 * v).norm(), 1e-9);
    EXPECT_NEAR(b->pairs[100].translation_m, (t_a - v).norm(), 1e-9);
    EXPECT_GT(std::abs(first.translation_m - b->pairs[100].translation_m), 0.01);
}

TEST(Rpe, GroundTruthGapsDropPairs) {
    Trajectory gt = constant_velocity({0.5, 0, 0}, 0.0);
    gt.erase(gt.begin() + 100, gt.begin() + 160);  // 2 s without ground truth
    const Trajectory est = constant_velocity({0.55, 0, 0}, 0.0);
    auto rpe = compute_rpe(gt, est);
    ASSERT_TRUE(rpe) << rpe.status().to_string();
    EXPECT_LT(rpe->pairs.size(), 270u);
    for (const RpePair& p : rpe->pairs) {
        EXPECT_LT(std::abs(p.gt_stamp_0_s - p.est_stamp_0_s), 2.0 / 30 + 1e-9);
        EXPECT_LT(std::abs(p.gt_stamp_1_s - p.est_stamp_1_s), 2.0 / 30 + 1e-9);
    }
    // Pairs whose est stamps have gt at the same time err by 5 cm; next to the gap an est pose
    // takes the gt pose one or two frames away (as TUM does), which shows in the spread.
    EXPECT_GT(rpe->pairs.size(), 150u);
    EXPECT_NEAR(rpe->translation_m.median, 0.05, 1e-9);
}

}  // namespace
}  // namespace df::eval
