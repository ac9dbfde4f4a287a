#pragma once
/// Which pixels of a frame belong to which object map (paper, Mapping; MaskFusion's matching):
/// every live object map is rendered into the frame (its prediction), a rigid instance of the
/// frame's segmentation matches the map whose rendered silhouette covers enough of it with the
/// same class, and a map also claims the pixels of its silhouette where the frame's depth agrees
/// with the rendered depth (the object seen but missed by the detector this frame). DDS-free:
/// plain label images and depth maps.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "dynamics/frame_segments.hpp"
#include "params/slam_params.hpp"

namespace df::objects {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Objects.Association), and generated into params/slam_params.hpp.
using AssociationConfig = params::slam::Objects::Association;

std::string validate(const AssociationConfig& config);

/// One object map as rendered into the current frame.
struct ObjectView {
    int class_id = -1;
    /// CV_32F metres, the rendered depth (camera z) of the map's surface, 0 where it shows none.
    cv::Mat depth_m;
};

/// What association decided for one frame. Views are referred to by their index in the input.
struct Association {
    /// Per view: the frame instance id matched to it (0: none).
    std::vector<uint16_t> instance_of_view;
    /// Per view: pixels it claims (matched instance and depth-agreeing silhouette).
    std::vector<int> pixels_of_view;
    /// Per view: of those, pixels only its silhouette gave (no instance claimed them).
    std::vector<int> silhouette_pixels_of_view;
    /// The frame's rigid instances no view matched, by id, and how many of each one's pixels a
    /// silhouette claimed anyway (an instance mostly claimed is a known object the detector
    /// named otherwise, not a new one).
    std::vector<uint16_t> unmatched_rigid;
    std::vector<int> unmatched_claimed;
    /// CV_16UC1, per pixel the index + 1 of the view that claims it, 0 none.
    cv::Mat view_labels;
};

/// Associates the frame's instances (`instances`, a label image of the frame's size with its
/// table) with the rendered object maps. `depth_m`: the frame's depth (CV_32F metres, 0
/// invalid), of the same size. `background_depth_m` (may be empty): the static map's rendered
/// depth; a silhouette pixel it explains as well (the floor an object stands on, which a map
/// may have taken in at its feet) stays the background's. Instances of non-rigid and unknown kinds
/// are never matched, and their pixels are never claimed by a silhouette (a person in front of a
/// car stays the person's). Where two silhouettes overlap the nearer surface wins. Greedy: pairs
/// are taken by decreasing overlap, each view and each instance at most once.
Association associate(const dynamics::LabelImage& instances, const std::vector<ObjectView>& views,
                      const cv::Mat& depth_m, const AssociationConfig& config,
                      const cv::Mat& background_depth_m = cv::Mat());

/// Motion segmentation's regions as candidate objects (objects.from_motion): each 8-connected
/// region of `motion_mask` (CV_8UC1, the frame's size) whose pixels lie outside every instance
/// of `instances` and outside every map's claim (`object_ids`, CV_16UC1, may be empty) becomes
/// a rigid instance of no class (class_id -1, score 1, its bounding box) in `instances` and an
/// unmatched one in `association`, when it has at least `min_pixels` such pixels and at least
/// half its pixels are such (a region mostly on a map is that map's). Labels are created when
/// `instances` has none. Returns how many regions were added.
int add_motion_regions(const cv::Mat& motion_mask, const cv::Mat& object_ids, int min_pixels,
                       dynamics::LabelImage* instances, Association* association);

/// True when `measured` (metres, > 0) agrees with `rendered` (metres, 0 = nothing rendered)
/// within tolerance_m + tolerance_per_m2 z^2.
inline bool depth_agrees(float measured, float rendered, float tolerance_m,
                         float tolerance_per_m2) {
    const float tolerance = tolerance_m + tolerance_per_m2 * rendered * rendered;
    return rendered > 0.f && measured - rendered <= tolerance && rendered - measured <= tolerance;
}
/// depth_agrees with an object map's rendering (depth_tolerance_*).
inline bool agrees_with_object(float measured, float rendered, const AssociationConfig& c) {
    return depth_agrees(measured, rendered, c.depth_tolerance_m, c.depth_tolerance_per_m2);
}
/// depth_agrees with the static map's rendering (background_tolerance_*).
inline bool agrees_with_background(float measured, float rendered, const AssociationConfig& c) {
    return depth_agrees(measured, rendered, c.background_tolerance_m,
                        c.background_tolerance_per_m2);
}

/// The ids of the rigid instances of `instances` that `association` left unmatched and whose
/// pixels with a depth the background's rendering explains (agrees_with_background) for at
/// least `fraction` of them: furniture that stands where the static map has it.
std::vector<uint16_t> explained_by_background(const dynamics::LabelImage& instances,
                                              const Association& association,
                                              const cv::Mat& depth_m,
                                              const cv::Mat& background_depth_m, float fraction,
                                              const AssociationConfig& config);

/// Intersection over union of two boxes (0 when either is empty).
float box_iou(const cv::Rect2f& a, const cv::Rect2f& b);

}  // namespace df::objects
