// The memory of rigid instances on a synthetic scene whose answer is known: a box at 1.5 m in
// front of a wall at 3 m, seen by a camera moving 1 cm per frame; the detector sees the box in
// the first frame only.
#include "dynamics/instance_memory.hpp"

#include <gtest/gtest.h>

namespace df::dynamics {
namespace {

constexpr int kW = 160, kH = 120;
constexpr float kF = 120.f, kCx = 79.5f, kCy = 59.5f;

struct View {
    cv::Mat vertex, depth, box;  // CV_32FC3, CV_32F, CV_8UC1 (truth: the box's pixels)
};

/// The scene from a camera at x = camera_x (axes as the world's); `box_there` false: the box
/// has gone and the wall shows behind it.
View view(float camera_x, bool box_there = true) {
    View v{cv::Mat(kH, kW, CV_32FC3), cv::Mat(kH, kW, CV_32F), cv::Mat::zeros(kH, kW, CV_8UC1)};
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            const float dx = (x - kCx) / kF, dy = (y - kCy) / kF;
            float z = 3.f;
            const float bx = camera_x + 1.5f * dx, by = 1.5f * dy;
            const bool on_box = box_there && bx > -0.2f && bx < 0.2f && by > -0.15f && by < 0.15f;
            if (on_box) z = 1.5f;
            v.vertex.at<cv::Vec3f>(y, x) = cv::Vec3f(z * dx, z * dy, z);
            v.depth.at<float>(y, x) = z;
            if (on_box) v.box.at<uint8_t>(y, x) = 255;
        }
    }
    return v;
}

double iou(const cv::Mat& a, const cv::Mat& b) {
    const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
    return uni > 0 ? inter / uni : 1.0;
}

Eigen::Isometry3f moved_by(float dx) {  // previous_T_current for a camera that moved dx along x
    Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
    t.translation() = Eigen::Vector3f(dx, 0.f, 0.f);
    return t;
}

TEST(InstanceMemory, KeepsAStaticBoxTheDetectorMissesUntilItsTimeIsUp) {
    InstanceMemoryConfig config;
    config.frames = 5;
    InstanceMemory memory;
    View v0 = view(0.f);
    memory.store(v0.box, v0.depth, config);
    const cv::Mat none = cv::Mat::zeros(kH, kW, CV_8UC1);
    for (int i = 1; i <= 8; ++i) {
        View v = view(0.01f * i);
        cv::Mat recalled = memory.recall(v.vertex, moved_by(0.01f), kF, kF, kCx, kCy, config);
        if (i <= config.frames) {
            EXPECT_GT(iou(recalled, v.box), 0.95) << "frame " << i;
        } else {
            EXPECT_EQ(cv::countNonZero(recalled), 0) << "frame " << i << ": remembered too long";
        }
        memory.store(none, v.depth, config);  // the detector misses it
    }
}

TEST(InstanceMemory, ADetectionStartsTheTimeAgain) {
    InstanceMemoryConfig config;
    config.frames = 3;
    InstanceMemory memory;
    const cv::Mat none = cv::Mat::zeros(kH, kW, CV_8UC1);
    for (int i = 0; i <= 10; ++i) {
        View v = view(0.01f * i);
        cv::Mat recalled = memory.recall(v.vertex, moved_by(0.01f), kF, kF, kCx, kCy, config);
        if (i > 0) {
            EXPECT_GT(iou(recalled, v.box), 0.95) << "frame " << i;
        }
        memory.store(i % 3 == 0 ? v.box : none, v.depth, config);  // seen every third frame
    }
}

TEST(InstanceMemory, AnObjectThatMovedAwayFreesWhatWasBehindIt) {
    InstanceMemoryConfig config;
    config.frames = 15;
    InstanceMemory memory;
    View v0 = view(0.f);
    memory.store(v0.box, v0.depth, config);
    View still = view(0.01f);
    EXPECT_GT(
        iou(memory.recall(still.vertex, moved_by(0.01f), kF, kF, kCx, kCy, config), still.box),
        0.95);  // the same memory keeps the box while it is there
    View v1 = view(0.01f, /*box_there=*/false);
    cv::Mat recalled = memory.recall(v1.vertex, moved_by(0.01f), kF, kF, kCx, kCy, config);
    EXPECT_EQ(cv::countNonZero(recalled), 0);
}

TEST(InstanceMemory, OffOrClearedRemembersNothing) {
    InstanceMemoryConfig off;
    off.frames = 0;
    InstanceMemory memory;
    View v0 = view(0.f), v1 = view(0.01f);
    memory.store(v0.box, v0.depth, off);
    EXPECT_EQ(memory.size(), 0);
    EXPECT_EQ(cv::countNonZero(memory.recall(v1.vertex, moved_by(0.01f), kF, kF, kCx, kCy, off)),
              0);
    InstanceMemoryConfig on;
    on.frames = 15;
    memory.store(v0.box, v0.depth, on);
    EXPECT_EQ(memory.size(), cv::countNonZero(v0.box));
    memory.clear();
    EXPECT_EQ(cv::countNonZero(memory.recall(v1.vertex, moved_by(0.01f), kF, kF, kCx, kCy, on)), 0);
}

TEST(InstanceMemory, OffByDefault) { EXPECT_EQ(InstanceMemoryConfig{}.frames, 0); }

TEST(InstanceMemory, ValidateNamesTheBadField) {
    InstanceMemoryConfig c;
    EXPECT_EQ(validate(c), "");
    c.frames = -1;
    EXPECT_NE(validate(c).find("frames"), std::string::npos);
    c = {};
    c.max_depth_difference_m = -0.1f;
    EXPECT_NE(validate(c).find("max_depth_difference_m"), std::string::npos);
}

}  // namespace
}  // namespace df::dynamics
