// Instances carried forward over frames without fresh detections (dynamics/instance_propagation):
// on generated sequences rendered in memory, the instances of one detected frame are carried
// over the next frames (each frame's own geometric segments, the true camera motion) and compared
// with the true instance masks of those frames.
#include "dynamics/instance_propagation.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/core.hpp>

#include "seg/frame_segmenter.hpp"
#include "sim/simulated_detector.hpp"
#include "sim_frames.hpp"

namespace df::dynamics {
namespace {

constexpr int kPersonClass = 0;  // COCO
constexpr int kCarClass = 2;

double iou(const cv::Mat& a, const cv::Mat& b) {
    const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
    return uni > 0 ? inter / uni : 0.0;
}

cv::Mat depth_metres(const io::RgbdImage& image) {
    cv::Mat z;
    image.depth.convertTo(z, CV_32F, 1.0 / image.depth_units_per_m);
    return z;
}

/// The frame's instances as the pipeline makes them: SIMULATED boxes fused with its geometric
/// segments; only the detections of `keep_class` (all when -1).
struct Segmented {
    LabelImage instances;
    seg::GeometricSegmentation geometric;
};
Segmented segment(const sim::Sequence& s, const test::SimFrame& f, int i, int keep_class) {
    const seg::FrameSegmenterConfig config;
    Segmented out;
    auto geometric = seg::segment_depth(f.image, config);
    EXPECT_TRUE(geometric.is_ok()) << geometric.status().message();
    out.geometric = *geometric;
    const sim::RenderBuffers truth = sim::render_frame(s, i);
    std::vector<detect::Detection> boxes =
        sim::simulate_detections(truth.instance, s.scene.objects, i, sim::SimulatedDetectorConfig{});
    std::vector<detect::Detection> kept;
    for (const detect::Detection& d : boxes)
        if (keep_class < 0 || d.class_id == keep_class) kept.push_back(d);
    const auto kind_of = [](const detect::Detection& d) {
        return d.class_name == "person" ? detect::ClassKind::kNonRigid : detect::ClassKind::kRigid;
    };
    auto fused = seg::fuse_segments(*geometric, kept, kind_of, config.instances);
    EXPECT_TRUE(fused.is_ok()) << fused.status().message();
    out.instances = fused->objects;
    return out;
}

/// The true mask of the scene's objects of `class_id` in frame i (walking_xyz has two persons).
cv::Mat truth_of(const sim::Sequence& s, int i, int class_id) {
    const sim::RenderBuffers truth = sim::render_frame(s, i);
    cv::Mat mask = cv::Mat::zeros(truth.instance.size(), CV_8UC1);
    for (size_t k = 0; k < s.scene.objects.size(); ++k)
        if (s.scene.objects[k].class_id == class_id) mask |= truth.instance == static_cast<int>(k + 1);
    EXPECT_GT(cv::countNonZero(mask), 0) << "no object of class " << class_id << " in frame " << i;
    return mask;
}

PinholeCamera camera_of(const io::RgbdImage& image) {
    const io::Intrinsics& k = image.intrinsics;
    return {static_cast<float>(k.fx), static_cast<float>(k.fy), static_cast<float>(k.cx),
            static_cast<float>(k.cy)};
}

/// The instance of class `class_id` in `image` as a mask (empty mask when none).
cv::Mat mask_of_class(const LabelImage& image, int class_id, cv::Size size) {
    cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
    if (image.empty()) return m;
    for (const InstanceInfo& row : image.instances)
        if (row.class_id == class_id) m |= image.labels == row.id;
    return m;
}

TEST(InstancePropagation, AWalkingPersonCarriedOverFiveFramesKeepsItsMask) {
    // walking_xyz: the person walks while the camera moves. Frame 0 is detected; frames 1-5 are
    // not, and get frame 0's person carried forward, one frame at a time.
    constexpr int kFrames = 6;
    const sim::Sequence s = test::make_noisy_sequence("walking_xyz", kFrames);
    InstancePropagation propagation;
    PropagationConfig config;
    test::SimFrame first = test::render_sim_frame(s, 0);
    Segmented detected = segment(s, first, 0, -1);
    const cv::Mat person0 = mask_of_class(detected.instances, kPersonClass, first.image.depth.size());
    ASSERT_GT(cv::countNonZero(person0), 2000) << "the detector's person in frame 0";
    propagation.store(detected.instances, depth_metres(first.image));
    Eigen::Isometry3d previous = first.world_T_camera;
    for (int i = 1; i < kFrames; ++i) {
        const test::SimFrame f = test::render_sim_frame(s, i);
        const Segmented own = segment(s, f, i, -1);
        const Eigen::Isometry3f current_T_previous =
            (f.world_T_camera.inverse() * previous).cast<float>();
        const cv::Mat depth = depth_metres(f.image);
        LabelImage carried = propagation.carry(depth, own.geometric.labels, own.geometric.count,
                                               current_T_previous, camera_of(f.image), config);
        ASSERT_FALSE(carried.empty()) << "frame " << i;
        int persons = 0;
        for (const InstanceInfo& row : carried.instances) {
            EXPECT_EQ(row.age, i) << "frames since the detector saw it";
            persons += row.class_id == kPersonClass;
        }
        ASSERT_GT(persons, 0) << "frame " << i << ": the persons are carried";
        const cv::Mat truth = truth_of(s, i, kPersonClass);
        const cv::Mat mask = mask_of_class(carried, kPersonClass, truth.size());
        const double carried_iou = iou(mask, truth);
        const double fresh_iou = iou(mask_of_class(own.instances, kPersonClass, mask.size()), truth);
        const double stale_iou = iou(person0, truth);
        std::printf("frame %d: persons IoU carried %.3f, fresh detection %.3f, frame 0's mask %.3f\n",
                    i, carried_iou, fresh_iou, stale_iou);
        // Five frames on, a carried mask is as good as a detection within 0.1.
        EXPECT_GT(carried_iou, fresh_iou - 0.1) << "frame " << i;
        EXPECT_GT(carried_iou, 0.6) << "frame " << i;
        propagation.store(carried, depth);
        previous = f.world_T_camera;
    }
}

TEST(InstancePropagation, ANewObjectGetsNoCarriedMask) {
    // room4 frame 0 with only the car detected: carried to frame 3, the car is there and
    // nothing else (the person, drum and furniture were never detected, so nothing is carried
    // onto them).
    const sim::Sequence s = test::make_noisy_sequence("room4", 4);
    const test::SimFrame first = test::render_sim_frame(s, 0);
    const Segmented detected = segment(s, first, 0, kCarClass);
    ASSERT_EQ(detected.instances.instances.size(), 1u) << "only the car is detected";
    InstancePropagation propagation;
    PropagationConfig config;
    propagation.store(detected.instances, depth_metres(first.image));
    Eigen::Isometry3d previous = first.world_T_camera;
    LabelImage carried;
    test::SimFrame f;
    for (int i = 1; i <= 3; ++i) {
        f = test::render_sim_frame(s, i);
        const Segmented own = segment(s, f, i, -1);
        const cv::Mat depth = depth_metres(f.image);
        carried = propagation.carry(depth, own.geometric.labels, own.geometric.count,
                                    (f.world_T_camera.inverse() * previous).cast<float>(),
                                    camera_of(f.image), config);
        ASSERT_FALSE(carried.empty()) << "frame " << i;
        std::printf("frame %d: car carried %d px, truth %d px, IoU %.3f; detected in frame 0: %d px\n", i,
                    cv::countNonZero(carried.labels), cv::countNonZero(truth_of(s, i, kCarClass)),
                    iou(carried.labels != 0, truth_of(s, i, kCarClass)),
                    cv::countNonZero(detected.instances.labels));
        propagation.store(carried, depth);
        previous = f.world_T_camera;
    }
    ASSERT_EQ(carried.instances.size(), 1u);
    EXPECT_EQ(carried.instances[0].class_id, kCarClass);
    const cv::Mat car = carried.labels != 0;
    const cv::Mat truth_car = truth_of(s, 3, kCarClass);
    EXPECT_GT(iou(car, truth_car), 0.6);
    // Of the carried pixels, nearly all are the car's (a few at its outline may be the floor's).
    const sim::RenderBuffers truth = sim::render_frame(s, 3);
    const cv::Mat other_objects = (truth.instance > 0) & ~truth_car;
    EXPECT_LT(cv::countNonZero(car & other_objects), 0.02 * cv::countNonZero(car))
        << "no other object gets the car's mask";
}

TEST(InstancePropagation, AnInstanceIsDroppedPastItsAgeAndForgottenOnClear) {
    const sim::Sequence s = test::make_noisy_sequence("walking_xyz", 4);
    const test::SimFrame first = test::render_sim_frame(s, 0);
    const Segmented detected = segment(s, first, 0, -1);
    ASSERT_FALSE(detected.instances.instances.empty());
    PropagationConfig config;
    config.max_age_frames = 2;
    InstancePropagation propagation;
    propagation.store(detected.instances, depth_metres(first.image));
    Eigen::Isometry3d previous = first.world_T_camera;
    for (int i = 1; i <= 3; ++i) {
        const test::SimFrame f = test::render_sim_frame(s, i);
        const Segmented own = segment(s, f, i, -1);
        const cv::Mat depth = depth_metres(f.image);
        LabelImage carried = propagation.carry(depth, own.geometric.labels, own.geometric.count,
                                               (f.world_T_camera.inverse() * previous).cast<float>(),
                                               camera_of(f.image), config);
        if (i <= 2) {
            ASSERT_FALSE(carried.empty()) << "frame " << i << " is within the age";
            for (const InstanceInfo& row : carried.instances) EXPECT_EQ(row.age, i);
        } else {
            EXPECT_TRUE(carried.empty()) << "frame " << i << " is past max_age_frames";
        }
        propagation.store(carried, depth);
        previous = f.world_T_camera;
    }
    propagation.store(detected.instances, depth_metres(first.image));
    propagation.clear();
    EXPECT_TRUE(propagation.empty());
    config.enabled = false;
    propagation.store(detected.instances, depth_metres(first.image));
    EXPECT_TRUE(propagation
                    .carry(depth_metres(first.image), detected.geometric.labels,
                           detected.geometric.count, Eigen::Isometry3f::Identity(),
                           camera_of(first.image), config)
                    .empty())
        << "off: nothing carried";
}

TEST(InstancePropagation, OnlyRowsWithPixelsAreHeldAndTheirAgeIsTheFreshest) {
    // A table row whose pixels are not in the label image (SlamSystem's rows for what object
    // maps claim) cannot be carried and must not make what is held look fresh.
    LabelImage frame;
    frame.labels = cv::Mat::zeros(40, 40, CV_16UC1);
    frame.labels(cv::Rect(5, 5, 10, 10)).setTo(1);
    InstanceInfo person;
    person.id = 1;
    person.class_id = kPersonClass;
    person.kind = ObjectKind::kNonRigid;
    person.age = 4;
    InstanceInfo claimed;
    claimed.id = 2;
    claimed.class_id = kCarClass;
    claimed.kind = ObjectKind::kRigid;
    claimed.age = 0;
    frame.instances = {person, claimed};
    InstancePropagation propagation;
    EXPECT_EQ(propagation.freshest_age(), -1);
    propagation.store(frame, cv::Mat(40, 40, CV_32F, cv::Scalar(2.f)));
    EXPECT_EQ(propagation.freshest_age(), 4);
    frame.instances = {claimed};
    propagation.store(frame, cv::Mat(40, 40, CV_32F, cv::Scalar(2.f)));
    EXPECT_TRUE(propagation.empty());
}

}  // namespace
}  // namespace df::dynamics
