#pragma once
/// The masks a frame comes with, as they cross the SlamSystem API and the topics: a label image
/// and a table of what each label is (instance, class, kind), plus, when known, the frame's
/// geometric segments (which motion segmentation grows its evidence over). DDS-free.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::dynamics {

/// The one definition of an instance's kind: rigid objects of a known class (mapped and tracked
/// once object maps exist), non-rigid ones of a known class (persons: only masked out), and
/// unknown movers (no class; found by motion segmentation).
enum class ObjectKind { kRigid, kNonRigid, kUnknown };
const char* to_string(ObjectKind kind);

/// One row of the table.
struct InstanceInfo {
    uint16_t id = 0;      ///< its value in the label image, 1..65535
    int class_id = -1;    ///< COCO index 0..79, -1 unknown
    float score = 0.f;    ///< detector score 0..1 (1 for motion segments and ground truth)
    ObjectKind kind = ObjectKind::kUnknown;
    cv::Rect2f box;       ///< detection box in the label image's pixels (empty when none)
    int pixels = 0;       ///< pixels with this id in the label image
    int age = 0;          ///< frames since the detector saw it (> 0: carried forward)
};

/// A label image with its table.
struct LabelImage {
    cv::Mat labels;  ///< CV_16UC1, 0 = none, else InstanceInfo::id; empty = no labels
    std::vector<InstanceInfo> instances;

    bool empty() const { return labels.empty(); }
    /// The table row of `id`, or nullptr.
    const InstanceInfo* find(uint16_t id) const;
};

/// Everything one frame brings besides its image.
struct FrameSegments {
    /// Object instances (detections fused with geometric segments, or ground truth).
    LabelImage objects;
    /// Geometric segments: CV_32SC1, 1..geometric_count, 0 = none (edge, invalid); may be empty.
    cv::Mat geometric;
    int geometric_count = 0;
    /// How old `objects`' detections are, in frames: 0 this frame's own (or ground truth), k > 0
    /// an earlier frame's boxes (reused), -1 none (no detector answered for this frame). A
    /// frame without its own detections gets the last frame's instances carried forward
    /// (dynamics/instance_propagation.hpp).
    int detections_age = 0;
};

/// OK when `segments` fits an image of `size`: label images of that size and type, every
/// non-zero label in the table, ids unique, geometric labels within 0..geometric_count.
/// kInvalidArgument naming `where` (e.g. "frame 12"), the image and the first bad value.
Status check(const FrameSegments& segments, cv::Size size, const std::string& where);

/// The segments at 1/factor of the resolution (nearest neighbour, as SlamSystem downscales
/// depth); boxes and pixel counts scaled alike. factor 1 returns a shallow copy.
FrameSegments downscale(const FrameSegments& segments, int factor);

/// A label image with a table of every id it holds, all of `kind` (class -1, score 1): for
/// masks without a table (ground truth, a user's masks). `labels`: CV_16UC1, or CV_8UC1 whose
/// non-zero pixels become id 1.
LabelImage from_labels(const cv::Mat& labels, ObjectKind kind);

/// CV_8UC1, 255 where `image.labels` holds an instance whose kind is in `kinds`; zeros of
/// `size` when the image is empty.
cv::Mat mask_of(const LabelImage& image, const std::vector<ObjectKind>& kinds, cv::Size size);

}  // namespace df::dynamics
