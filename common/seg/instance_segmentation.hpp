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
#include "params/fusion_params.hpp"

namespace df::seg {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/fusion.proto (InstanceParams), and generated into params/fusion_params.hpp.
using InstanceSegmentationConfig = params::fusion::InstanceParams;

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
