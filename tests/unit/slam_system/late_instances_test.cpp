// Object segments that arrive after their frame was tracked (a detector slower than the camera,
// the SLAM service's segments deadline passed): SlamSystem::take_late_instances hands them to
// propagation, and the next frames carry the detector's newest instances, with their age, in
// place of older ones. On generated walking_xyz frames rendered in memory, SIMULATED boxes
// fused with each frame's geometric segments.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "seg/frame_segmenter.hpp"
#include "sim/simulated_detector.hpp"
#include "sim_frames.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam {
namespace {

constexpr int kPersonClass = 0;  // COCO

dynamics::FrameSegments segments_of(const sim::Sequence& s, const test::SimFrame& f, int i) {
    const seg::FrameSegmenterConfig config;
    auto geometric = seg::segment_depth(f.image, config);
    EXPECT_TRUE(geometric.is_ok()) << geometric.status().message();
    const sim::RenderBuffers truth = sim::render_frame(s, i);
    const auto boxes = sim::simulate_detections(truth.instance, s.scene.objects, i,
                                                sim::SimulatedDetectorConfig{});
    const auto kind_of = [](const detect::Detection& d) {
        return d.class_name == "person" ? detect::ClassKind::kNonRigid : detect::ClassKind::kRigid;
    };
    auto fused = seg::fuse_segments(*geometric, boxes, kind_of, config.instances);
    EXPECT_TRUE(fused.is_ok()) << fused.status().message();
    return *fused;
}

double person_iou(const sim::Sequence& s, int i, const dynamics::LabelImage& used) {
    const sim::RenderBuffers truth = sim::render_frame(s, i);
    cv::Mat gt = cv::Mat::zeros(truth.instance.size(), CV_8UC1);
    for (size_t k = 0; k < s.scene.objects.size(); ++k)
        if (s.scene.objects[k].class_id == kPersonClass)
            gt |= truth.instance == static_cast<int>(k + 1);
    // `used` is at the processing resolution: compare there.
    cv::Mat small;
    cv::resize(gt, small, used.labels.size(), 0, 0, cv::INTER_NEAREST);
    cv::Mat mask = cv::Mat::zeros(used.labels.size(), CV_8UC1);
    for (const dynamics::InstanceInfo& row : used.instances)
        if (row.class_id == kPersonClass) mask |= used.labels == row.id;
    const double inter = cv::countNonZero(mask & small), uni = cv::countNonZero(mask | small);
    return uni > 0 ? inter / uni : 0.0;
}

TEST(LateInstances, DetectionsThatAlwaysArriveLateStillGiveTheFramesMasks) {
    // No frame's detections arrive in time (a detector slower than the SLAM service's segments
    // deadline). Without the late path no frame has instances at all; with it, frame 7's
    // detections, arriving after frame 9 was tracked, are carried into frame 10 (age 3).
    constexpr int kFrames = 11;
    const sim::Sequence s = test::make_noisy_sequence("walking_xyz", kFrames);
    for (int late : {0, 1}) {
        auto created = SlamSystem::create(SystemConfig{});
        ASSERT_TRUE(created.is_ok()) << created.status().message();
        SlamSystem system = std::move(created).value();
        dynamics::FrameSegments frame7;
        int64_t frame7_ns = 0;
        for (int i = 0; i < kFrames; ++i) {
            const test::SimFrame f = test::render_sim_frame(s, i);
            dynamics::FrameSegments segments = segments_of(s, f, i);
            if (i == 7) {
                frame7 = segments;
                frame7_ns = f.image.sensor_ns;
            }
            segments.objects = dynamics::LabelImage{};
            segments.detections_age = -1;  // none in time
            if (late && i == 10) {
                EXPECT_TRUE(system.take_late_instances(frame7_ns, frame7.objects));
                // Once held, the same frame's (no fresher) are not taken, nor those of a frame 200 ms
                // from any tracked one.
                EXPECT_FALSE(system.take_late_instances(frame7_ns, frame7.objects));
                EXPECT_FALSE(system.take_late_instances(frame7_ns + 200'000'000, frame7.objects));
            }
            auto report = system.process(f.image, segments);
            ASSERT_TRUE(report.is_ok()) << report.status().message();
            if (i < kFrames - 1) continue;
            int age = -1;
            for (const dynamics::InstanceInfo& row : report->instances.instances)
                if (row.class_id == kPersonClass) age = age < 0 ? row.age : std::min(age, row.age);
            if (!late) {
                EXPECT_EQ(report->carried, 0);
                EXPECT_EQ(age, -1) << "no person: nothing was ever detected in time";
                continue;
            }
            ASSERT_GT(report->carried, 0);
            const double iou = person_iou(s, i, report->instances);
            std::printf("frame 10: persons IoU %.3f from frame 7's late detections (age %d)\n",
                        iou, age);
            EXPECT_EQ(age, 3);
            EXPECT_GT(iou, 0.5);
        }
    }
}

}  // namespace
}  // namespace df::slam
