#pragma once
/// Motion segmentation of unknown movers (DetectFusion, "Motion Segmentation"): the per-pixel
/// geometric residuals of the current frame registered against the static map's prediction are
/// split into two clusters by 2-means; the higher cluster is the candidate dynamic region, which
/// is grown to whole objects over the frame's geometric segments.
///
/// Where the paper is thin, this does more (docs/dynamics.md):
/// - a depth-dependent noise floor: a pixel is dynamic only when its residual is above both the
///   2-means split and the sensor's noise at its depth (so a static scene, whose two clusters are
///   both noise, flags next to nothing), and the whole frame is static when the clusters' centroids
///   are too close or too few pixels are dynamic;
/// - evidence per segment: a geometric segment becomes dynamic only when enough of its pixels
///   with a residual are dynamic (the paper's IoU rule, as a fraction of the segment);
/// - carried forward: the previous frame's motion mask, warped into this frame by the tracked
///   camera motion, lowers the evidence a segment needs, so a mover that slows or pauses for a
///   frame is not fused into the map.
/// DDS-free.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "core/status.hpp"
#include "dynamics/two_means.hpp"
#include "params/slam_params.hpp"

namespace df::dynamics {

/// Every threshold (units in the names).
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Motion), and generated into params/slam_params.hpp.
using MotionSegmentationConfig = params::slam::Motion;

/// Empty when usable, else the bad field and its value.
std::string validate(const MotionSegmentationConfig& config);

/// One frame's inputs; every image has the frame's (processing) size.
struct MotionInput {
    /// CV_32F, metres: geometric residual of each frame pixel against the static model at the
    /// frame's estimated pose (slam::track's residual image; its sign is ignored here); NaN where
    /// there is none (no depth, no model).
    cv::Mat residual_m;
    /// CV_32F, metres, 0 = invalid: the frame's depth (for the noise floor).
    cv::Mat depth_m;
    /// CV_8UC1 or empty: pixels already left out (object instances); not clustered, never
    /// flagged.
    cv::Mat excluded;
    /// CV_32SC1 geometric segments 1..geometric_count, 0 = none; may be empty.
    cv::Mat geometric;
    int geometric_count = 0;
    /// CV_8UC1 or empty: the previous frame's motion mask warped into this frame (warp_mask).
    cv::Mat carried;
    /// CV_32F or empty: |intensity - model intensity| per pixel, NaN where none.
    cv::Mat photometric;
};

struct MotionResult {
    cv::Mat mask;           ///< CV_8UC1, 255 = dynamic (unknown mover)
    TwoMeans clusters;      ///< of the clipped residuals
    bool moving = false;    ///< false: the guards found no motion (mask all 0)
    int residual_pixels = 0;  ///< pixels clustered
    int dynamic_pixels = 0;   ///< above the split and the noise floor, before growing
    int segments = 0;         ///< geometric segments (or regions) made dynamic
    int mask_pixels = 0;      ///< non-zero pixels of `mask`
};

/// Segments one frame. kInvalidArgument naming the input whose type or size is wrong.
Result<MotionResult> segment_motion(const MotionInput& input,
                                    const MotionSegmentationConfig& config);

/// `previous` (CV_8UC1 mask of the previous frame) as seen from the current frame: each current
/// pixel with a vertex (CV_32FC3, current camera frame, metres; z <= 0 invalid) is moved into the
/// previous camera by previous_T_current and looks the mask up at its projection (intrinsics fx,
/// fy, cx, cy of both frames). Pixels without a vertex take the previous mask at the same pixel.
cv::Mat warp_mask(const cv::Mat& previous, const cv::Mat& vertex,
                  const Eigen::Isometry3f& previous_T_current, float fx, float fy, float cx,
                  float cy);

}  // namespace df::dynamics
