#pragma once
/// One frame's segments as the pipeline's services make them, for callers that run them in one
/// process (df_slam offline): the geometric segmentation of the depth image (what df_geoseg
/// publishes) and its fusion with detector boxes into object instances (what df_fusion
/// publishes), as a dynamics::FrameSegments. DDS-free.
#include <vector>

#include "core/status.hpp"
#include "detect/detection.hpp"
#include "dynamics/frame_segments.hpp"
#include "io/rgbd_image.hpp"
#include "seg/geometric_segmentation.hpp"
#include "seg/instance_segmentation.hpp"
#include "slam/slam_config.hpp"

namespace df::seg {

struct FrameSegmenterConfig {
    /// Depth to vertices and normals (one level: only full resolution is segmented; its
    /// max_depth_m and normal_baseline_px are geometric's).
    slam::PreprocessConfig preprocess = [] {
        slam::PreprocessConfig p;
        p.pyramid_levels = 1;
        return p;
    }();
    GeometricSegmentationConfig geometric;
    InstanceSegmentationConfig instances;
};

/// The geometric segments of `image` at its resolution. kInvalidArgument for an unusable image.
Result<GeometricSegmentation> segment_depth(const io::RgbdImage& image,
                                            const FrameSegmenterConfig& config);

/// `geometric` fused with `detections` (boxes in the same pixels): object instances of the kinds
/// `kind_of` gives (kIgnored classes make none), with the geometric segments alongside.
Result<dynamics::FrameSegments> fuse_segments(const GeometricSegmentation& geometric,
                                              const std::vector<detect::Detection>& detections,
                                              const ClassKindOf& kind_of,
                                              const InstanceSegmentationConfig& config);

/// Appends to `out`'s table a row with 0 pixels for each non-rigid detection that made no
/// instance (no segment explained it), so that the invalid mask can still claim its box
/// (dynamics::InvalidMaskConfig::non_rigid_box_depth_m). Ids follow the instances'.
void add_unsegmented_detections(const std::vector<detect::Detection>& detections,
                                const InstanceSegmentation& instances, const ClassKindOf& kind_of,
                                dynamics::LabelImage* out);

/// An InstanceSegmentation as the label image and table dynamics uses.
dynamics::LabelImage to_label_image(const InstanceSegmentation& instances);

}  // namespace df::seg
