// The invalid mask and the label-image API: which kinds are left out, the depth-gated person box,
// the fuse-behind-the-model exception, labels and table, and checks naming what is wrong.
#include <gtest/gtest.h>

#include <limits>

#include "dynamics/frame_segments.hpp"
#include "dynamics/invalid_mask.hpp"

namespace df::dynamics {
namespace {

constexpr int kW = 80, kH = 60;

/// A table row: instance `id` of class `class_id` and `kind`, detected in `box`.
InstanceInfo row(uint16_t id, int class_id, ObjectKind kind, cv::Rect2f box) {
    InstanceInfo i;
    i.id = id;
    i.class_id = class_id;
    i.kind = kind;
    i.box = box;
    return i;
}

/// A person (id 3, non-rigid, box 10..29 x 10..49) and a cup (id 8, rigid, box 50..59 x 20..29).
FrameSegments two_instances() {
    FrameSegments s;
    s.objects.labels = cv::Mat::zeros(kH, kW, CV_16UC1);
    s.objects.labels(cv::Rect(12, 12, 10, 30)).setTo(3);
    s.objects.labels(cv::Rect(50, 20, 10, 10)).setTo(8);
    s.objects.instances = {row(3, 0, ObjectKind::kNonRigid, cv::Rect2f(10, 10, 20, 40)),
                           row(8, 41, ObjectKind::kRigid, cv::Rect2f(50, 20, 10, 10))};
    return s;
}

TEST(InvalidMask, KindsLeftOutAsConfigured) {
    const FrameSegments s = two_instances();
    InvalidMaskConfig c;
    c.instance_dilate_px = 0;
    cv::Mat m = instance_mask(s, cv::Mat(), cv::Size(kW, kH), c);
    EXPECT_EQ(cv::countNonZero(m), 300 + 100);
    c.rigid = false;
    m = instance_mask(s, cv::Mat(), cv::Size(kW, kH), c);
    EXPECT_EQ(cv::countNonZero(m), 300);
    EXPECT_EQ(m.at<uint8_t>(25, 55), 0);
    c.instance_dilate_px = 1;
    m = instance_mask(s, cv::Mat(), cv::Size(kW, kH), c);
    EXPECT_EQ(cv::countNonZero(m), 12 * 32);
}

TEST(InvalidMask, APersonClaimsItsBoxAtItsOwnDepthOnly) {
    const FrameSegments s = two_instances();
    // The person at 1.5 m (its segments cover only part of it); inside its box an arm at 1.6 m
    // that no segment took, and the wall behind at 3 m.
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(3.f));
    depth(cv::Rect(12, 12, 10, 30)).setTo(1.5f);
    depth(cv::Rect(22, 20, 6, 8)).setTo(1.6f);
    InvalidMaskConfig c;
    c.instance_dilate_px = 0;
    const cv::Mat m = instance_mask(s, depth, cv::Size(kW, kH), c);
    EXPECT_EQ(m.at<uint8_t>(24, 25), 255) << "the arm inside the box";
    EXPECT_EQ(m.at<uint8_t>(45, 25), 0) << "the wall behind, inside the box";
    EXPECT_EQ(m.at<uint8_t>(24, 35), 0) << "outside the box";
    c.non_rigid_box_depth_m = 0.f;
    EXPECT_EQ(instance_mask(s, depth, cv::Size(kW, kH), c).at<uint8_t>(24, 25), 0);
}

TEST(InvalidMask, AnUnsegmentedPersonsBoxPixelsCarryItsIdInTheLabels) {
    // A person the detector found but no segment explained: a table row with 0 pixels and its
    // box (40..69 x 5..54); inside it the person at 1.2 m, the wall behind at 3 m.
    FrameSegments s;
    s.objects.labels = cv::Mat::zeros(kH, kW, CV_16UC1);
    s.objects.instances = {row(5, 0, ObjectKind::kNonRigid, cv::Rect2f(40, 5, 30, 50))};
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(3.f));
    depth(cv::Rect(48, 8, 12, 44)).setTo(1.2f);
    InvalidMaskConfig c;
    c.instance_dilate_px = 0;
    const cv::Mat ids = instance_labels(s, depth, cv::Size(kW, kH), c);
    EXPECT_EQ(ids.at<uint16_t>(30, 50), 5) << "the person's pixels carry its id";
    EXPECT_EQ(ids.at<uint16_t>(30, 42), 0) << "the wall inside the box stays";
    EXPECT_EQ(cv::countNonZero(ids), 12 * 44);
    const InvalidMask m = combine(s, ids, cv::Mat(), cv::Mat(), c);
    ASSERT_EQ(m.labels.instances.size(), 1u) << "the published table names the person";
    EXPECT_EQ(m.labels.instances[0].id, 5);
    EXPECT_EQ(m.labels.instances[0].pixels, 12 * 44);
    EXPECT_EQ(cv::countNonZero(m.tracking), 12 * 44);
}

TEST(InvalidMask, CombineLabelsInstancesThenMotionRegions) {
    const FrameSegments s = two_instances();
    InvalidMaskConfig c;
    c.instance_dilate_px = 0;
    const cv::Mat instances = instance_labels(s, cv::Mat(), cv::Size(kW, kH), c);
    cv::Mat motion = cv::Mat::zeros(kH, kW, CV_8UC1);
    motion(cv::Rect(65, 40, 8, 8)).setTo(255);
    cv::Mat residual(kH, kW, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
    residual(cv::Rect(65, 40, 4, 8)).setTo(0.5f);   // farther than the model: seen through it
    residual(cv::Rect(69, 40, 4, 8)).setTo(-0.5f);  // nearer: an occluding mover
    const InvalidMask m = combine(s, instances, motion, residual, c);
    EXPECT_EQ(cv::countNonZero(m.tracking), 300 + 100 + 64);
    EXPECT_EQ(cv::countNonZero(m.fusion), 300 + 100 + 32) << "the seen-through half is fused";
    ASSERT_EQ(m.labels.instances.size(), 3u);
    EXPECT_EQ(m.labels.labels.at<uint16_t>(20, 15), 3);
    EXPECT_EQ(m.labels.labels.at<uint16_t>(25, 55), 8);
    const InstanceInfo& mover = m.labels.instances[2];
    EXPECT_EQ(mover.kind, ObjectKind::kUnknown);
    EXPECT_EQ(mover.id, 9) << "after the largest instance id";
    EXPECT_EQ(mover.pixels, 64);
    EXPECT_EQ(m.labels.labels.at<uint16_t>(44, 68), 9);
}

TEST(FrameSegmentsCheck, NamesTheFrameAndTheBadValue) {
    FrameSegments s = two_instances();
    EXPECT_TRUE(check(s, cv::Size(kW, kH), "frame 4").is_ok());
    Status st = check(s, cv::Size(kW * 2, kH * 2), "frame 4");
    ASSERT_FALSE(st.is_ok());
    EXPECT_NE(st.message().find("frame 4: object label image is CV_16UC1 80x60, the frame 160x120"),
              std::string::npos)
        << st.message();
    s.objects.labels.at<uint16_t>(5, 7) = 77;
    st = check(s, cv::Size(kW, kH), "frame 4");
    ASSERT_FALSE(st.is_ok());
    EXPECT_NE(st.message().find("object label 77 at pixel (7, 5) is not in the instance table"),
              std::string::npos)
        << st.message();
    s = two_instances();
    s.geometric = cv::Mat(kH, kW, CV_32S, cv::Scalar(9));
    s.geometric_count = 4;
    st = check(s, cv::Size(kW, kH), "frame 4");
    ASSERT_FALSE(st.is_ok());
    EXPECT_NE(st.message().find("outside 0..4"), std::string::npos) << st.message();
}

TEST(FrameSegmentsCheck, FromLabelsAndDownscaleKeepTheTable) {
    cv::Mat gt = cv::Mat::zeros(kH, kW, CV_16UC1);
    gt(cv::Rect(0, 0, 10, 10)).setTo(2);
    gt(cv::Rect(20, 20, 4, 4)).setTo(5);
    FrameSegments s;
    s.objects = from_labels(gt, ObjectKind::kUnknown);
    ASSERT_EQ(s.objects.instances.size(), 2u);
    EXPECT_EQ(s.objects.instances[0].id, 2);
    EXPECT_EQ(s.objects.instances[0].pixels, 100);
    EXPECT_TRUE(check(s, gt.size(), "frame 0").is_ok());
    const FrameSegments half = downscale(s, 2);
    EXPECT_EQ(half.objects.labels.size(), cv::Size(kW / 2, kH / 2));
    EXPECT_EQ(half.objects.find(2)->pixels, 25);
    EXPECT_EQ(half.objects.find(5)->pixels, 4);
}

}  // namespace
}  // namespace df::dynamics
