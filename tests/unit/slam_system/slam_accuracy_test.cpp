// The SLAM system on generated static scenes (Kinect-like noise on): the camera trajectory it
// estimates against the generator's ground truth (TUM ATE), and a deliberate jump it must report
// as lost instead of fusing a wrong pose.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>

#include "eval/trajectory_metrics.hpp"
#include "sim_frames.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam {
namespace {

// Three seconds of camera motion (frame-to-model drift, if any, shows over this length).
constexpr int kFrames = 90;

sim::Sequence make(const std::string& preset, int frames) {
    return test::make_noisy_sequence(preset, frames);
}

io::StampedPose stamped(const io::RgbdImage& image, const Eigen::Isometry3d& pose) {
    io::StampedPose p;
    p.stamp_s = static_cast<double>(image.sensor_ns) * 1e-9;
    p.t = pose.translation();
    p.q = Eigen::Quaterniond(pose.linear());
    return p;
}

struct RunResult {
    double ate_rmse_m = -1;
    uint64_t lost = 0;
    size_t surfels = 0;
};

RunResult run(const std::string& preset, int frames, const SystemConfig& config) {
    const sim::Sequence s = make(preset, frames);
    auto system = SlamSystem::create(config);
    EXPECT_TRUE(system.is_ok()) << system.status().message();
    std::vector<io::StampedPose> gt;
    for (int i = 0; i < s.frames; ++i) {
        const test::SimFrame f = test::render_sim_frame(s, i);
        gt.push_back(stamped(f.image, f.world_T_camera));
        auto report = system->process(f.image);
        EXPECT_TRUE(report.is_ok()) << report.status().message();
        EXPECT_EQ(report->tracking.state, TrackingState::kOk)
            << preset << " frame " << i << ": " << report->tracking.reason;
    }
    RunResult r;
    auto ate = eval::compute_ate(gt, system->trajectory());
    EXPECT_TRUE(ate.is_ok()) << ate.status().message();
    if (ate.is_ok()) r.ate_rmse_m = ate->translation_m.rmse;
    r.lost = system->lost_frames();
    r.surfels = system->static_map().size();
    return r;
}

TEST(SlamAccuracy, XyzMotionAteBelowOneCentimetre) {
    const RunResult r = run("static_xyz", kFrames, SystemConfig{});
    std::printf("static_xyz %d frames: ATE RMSE %.2f mm, %zu surfels\n", kFrames, r.ate_rmse_m * 1000,
                r.surfels);
    EXPECT_EQ(r.lost, 0u);
    EXPECT_GE(r.ate_rmse_m, 0.0);
    EXPECT_LE(r.ate_rmse_m, 0.010);
}

TEST(SlamAccuracy, FastBlurredCameraIsNotLost) {
    // static_fast: up to 2 cm per frame with motion blur. Around frame 107 the camera looks down
    // over the desk: the sensor's depth steps make half the frame's normals disagree with the
    // model's by more than the ICP normal gate although the pose is right, and counting those as
    // outliers reported the frame lost (then every later one: a lost frame is not fused).
    const RunResult r = run("static_fast", 115, SystemConfig{});
    std::printf("static_fast 115 frames: ATE RMSE %.2f mm, %zu surfels\n", r.ate_rmse_m * 1000,
                r.surfels);
    EXPECT_EQ(r.lost, 0u);
    EXPECT_GE(r.ate_rmse_m, 0.0);
    EXPECT_LE(r.ate_rmse_m, 0.010);
}

TEST(SlamAccuracy, HalfsphereMotionAteBelowOneCentimetre) {
    const RunResult r = run("static_halfsphere", kFrames, SystemConfig{});
    std::printf("static_halfsphere %d frames: ATE RMSE %.2f mm, %zu surfels\n", kFrames,
                r.ate_rmse_m * 1000, r.surfels);
    EXPECT_EQ(r.lost, 0u);
    EXPECT_GE(r.ate_rmse_m, 0.0);
    EXPECT_LE(r.ate_rmse_m, 0.010);
}

TEST(SlamAccuracy, HalfsphereMotionAtFullResolutionAteBelowOneCentimetre) {
    SystemConfig config;
    config.system.processing_downscale = 1;
    const RunResult r = run("static_halfsphere", kFrames, config);
    std::printf("static_halfsphere %d frames, full resolution: ATE RMSE %.2f mm, %zu surfels\n",
                kFrames, r.ate_rmse_m * 1000, r.surfels);
    EXPECT_GE(r.ate_rmse_m, 0.0);
    EXPECT_LE(r.ate_rmse_m, 0.01);
    EXPECT_EQ(r.lost, 0u);
}

TEST(SlamAccuracy, StillCameraStaysPutForManyFrames) {
    // One noisy frame fed 120 times: the estimate must not move. (Regression: a rotation that
    // was not kept orthonormal grew its scale error 3x per frame through Isometry3d::inverse()
    // and ran the pose away along the optical axis after about 25 frames.)
    const sim::Sequence s = make("static_xyz", 1);
    const test::SimFrame f = test::render_sim_frame(s, 0);
    auto system = SlamSystem::create(SystemConfig{}, f.world_T_camera);
    ASSERT_TRUE(system.is_ok()) << system.status().message();
    Eigen::Isometry3d settled = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d halfway = Eigen::Isometry3d::Identity();
    double settled_from_start_m = 0.0, halfway_from_start_m = 0.0;
    for (int i = 0; i < 120; ++i) {
        auto report = system->process(f.image);
        ASSERT_TRUE(report.is_ok()) << report.status().message();
        ASSERT_EQ(report->tracking.state, TrackingState::kOk)
            << "frame " << i << ": " << report->tracking.reason;
        // Within noise of the start (the model is an average, the frame one noisy sample;
        // measured 1.1 mm at frame 20, 1.7 mm at frame 119) ...
        const Eigen::Isometry3d moved = f.world_T_camera.inverse() * system->world_T_camera();
        ASSERT_LT(moved.translation().norm(), 3e-3) << "frame " << i;
        ASSERT_LT(Eigen::AngleAxisd(moved.linear()).angle(), 2e-3) << "frame " << i;
        const Eigen::Matrix3d r = system->world_T_camera().linear();
        ASSERT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-9)
            << "frame " << i;
        if (i == 20) {
            settled = system->world_T_camera();
            settled_from_start_m = moved.translation().norm();
        }
        if (i == 70) {
            halfway = system->world_T_camera();
            halfway_from_start_m = moved.translation().norm();
        }
    }
    // ... and, once the map has settled, creeping less than 2 mm in 100 frames, and moving away
    // from the start more slowly in the second half than in the first (the pre-fix runaway grew
    // 3x per frame). Measured 2026-12-04 (splats of 1 px): 0.40 mm in 100 frames, 0.53 mm
    // from the start at frame 20, 0.75 at 70, 0.86 at 119: the estimate wanders within a
    // fraction of a millimetre (0.21 mm between frames 20 and 70, 0.32 between 70 and 119)
    // while its distance from the start levels off.
    const Eigen::Isometry3d creep = settled.inverse() * system->world_T_camera();
    const double first_half_m = (settled.inverse() * halfway).translation().norm();
    const double second_half_m = (halfway.inverse() * system->world_T_camera()).translation().norm();
    const double end_from_start_m =
        (f.world_T_camera.inverse() * system->world_T_camera()).translation().norm();
    std::printf("still camera: creep %.3f mm in 100 frames (%.3f then %.3f mm); from the start "
                "%.3f, %.3f, %.3f mm at frames 20, 70, 119\n",
                creep.translation().norm() * 1e3, first_half_m * 1e3, second_half_m * 1e3,
                settled_from_start_m * 1e3, halfway_from_start_m * 1e3, end_from_start_m * 1e3);
    EXPECT_LT(creep.translation().norm(), 2e-3);
    EXPECT_LT(second_half_m, 1e-3) << "the estimate must not wander off";
    EXPECT_LT(end_from_start_m - halfway_from_start_m, halfway_from_start_m - settled_from_start_m)
        << "the creep away from the start must slow down";
    EXPECT_LT(Eigen::AngleAxisd(creep.linear()).angle(), 1e-3);
}

TEST(SlamAccuracy, UnrecoverableJumpIsReportedLostNotAWrongPose) {
    // static_jump: at 1 s (frame 30) the camera turns 120 degrees on the spot.
    const sim::Sequence s = make("static_jump", 40);
    auto system = SlamSystem::create(SystemConfig{});
    ASSERT_TRUE(system.is_ok()) << system.status().message();
    Eigen::Isometry3d gt_T_est = Eigen::Isometry3d::Identity();
    int lost_after_jump = 0, wrong_ok_after_jump = 0;
    for (int i = 0; i < s.frames; ++i) {
        const test::SimFrame f = test::render_sim_frame(s, i);
        auto report = system->process(f.image);
        ASSERT_TRUE(report.is_ok()) << report.status().message();
        if (i == 0) gt_T_est = f.world_T_camera * report->world_T_camera.inverse();
        const bool after_jump = s.time_s(i) >= 1.0;
        const double error_m =
            ((gt_T_est * report->world_T_camera).translation() - f.world_T_camera.translation())
                .norm();
        const double angle_rad = Eigen::AngleAxisd((gt_T_est * report->world_T_camera).linear() *
                                                   f.world_T_camera.linear().transpose())
                                     .angle();
        if (!after_jump) {
            EXPECT_EQ(report->tracking.state, TrackingState::kOk) << "frame " << i;
            continue;
        }
        if (report->tracking.state == TrackingState::kLost) {
            ++lost_after_jump;
            EXPECT_FALSE(report->fused) << "a lost frame must not be fused (frame " << i << ")";
            EXPECT_FALSE(report->tracking.reason.empty());
        } else if (error_m > 0.05 || angle_rad > 0.1) {
            ++wrong_ok_after_jump;
        }
    }
    EXPECT_GT(lost_after_jump, 0) << "the jump was not detected";
    EXPECT_EQ(wrong_ok_after_jump, 0) << "frames after the jump reported ok with a wrong pose";
    EXPECT_EQ(system->lost_frames(), static_cast<uint64_t>(lost_after_jump));
}

}  // namespace
}  // namespace df::slam
