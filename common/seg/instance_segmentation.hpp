#pragma once
/// DetectFusion's instance segmentation at frame rate: detector boxes intersected with the
/// geometric segments of the depth image. For each box, the IoU of every segment with the box;
/// boxes are visited smallest first and a segment goes to the first box where its IoU passes the
/// threshold. The union of a box's segments, clipped to the box, is the instance's mask.
/// Extension (InstanceSegmentationConfig::min_inside_fraction): objects that folds split into
/// parts (limbs, occluded cars) also keep the parts lying inside their box at the depth of the
/// best part. DDS-free.
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "detect/detection.hpp"

namespace df::seg {

struct InstanceSegmentationConfig {
    /// A segment joins a box when |segment n box| / |segment u box| (pixels) reaches this. The
    /// paper's rule; a box holds one object, so an object split into several segments keeps
    /// only those that fill enough of the box.
    float min_iou = 0.2f;
    /// ... or, additionally, when at least this fraction of the segment lies inside the box and
    /// the segment's median depth is within `max_depth_from_core_m` of the depth of the box's
    /// best (highest IoU) segment: the other parts of an object split by folds. > 1 disables.
    float min_inside_fraction = 0.9f;
    float max_depth_from_core_m = 0.5f;
    /// When no segment passes min_iou, the largest segment lying inside the box (by
    /// min_inside_fraction) becomes the core if it covers at least this fraction of the box.
    float min_core_box_fraction = 0.05f;
    /// When neither rule finds a core, the segment filling the most of the box becomes it if it
    /// fills at least this fraction (its pixels inside the box form the mask). > 1 disables.
    float min_fill_fraction = 0.4f;
    /// Boxes whose best mask has fewer pixels than this give no instance.
    int min_instance_pixels = 100;
};

std::string validate(const InstanceSegmentationConfig& config);

/// One instance: a detection and the pixels assigned to it.
struct Instance {
    int id = 0;  ///< value in InstanceSegmentation::labels, 1..
    detect::Detection detection;
    detect::ClassKind kind = detect::ClassKind::kRigid;
    int pixels = 0;
};

struct InstanceSegmentation {
    cv::Mat labels;          ///< CV_16UC1, instance id, 0 = none
    cv::Mat rigid_mask;      ///< CV_8UC1, 255 on instances of rigid classes
    cv::Mat non_rigid_mask;  ///< CV_8UC1, 255 on instances of non-rigid classes (persons)
    std::vector<Instance> instances;
};

/// Tells how a class is treated; detections of kIgnored classes make no instance.
using ClassKindOf = std::function<detect::ClassKind(const detect::Detection&)>;

/// Fuses `detections` (boxes in the pixels of `segment_labels`) with the geometric segments
/// `segment_labels` (CV_32SC1, 1..segment_count, 0 = none; see geometric_segmentation.hpp)
/// and the camera-frame depth `depth_m` (CV_32FC1, metres, 0 = invalid; used by the
/// inside-fraction rule). Instances are numbered in the order of `detections` that produced them.
Result<InstanceSegmentation> segment_instances(const cv::Mat& segment_labels, int segment_count,
                                               const cv::Mat& depth_m,
                                               const std::vector<detect::Detection>& detections,
                                               const ClassKindOf& kind_of,
                                               const InstanceSegmentationConfig& config = {});

}  // namespace df::seg
