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
///   frame is not fused into the map;
/// - still but unmapped: a segment or region that is dynamic by its residual is dropped when an
///   older frame saw it where it is now as a rigid instance, and never through it
///   (history_evidence): the static map lacks it because a detection kept it out; it did not
///   move.
/// DDS-free.
#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "core/status.hpp"
#include "dynamics/projections.hpp"
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
    /// CV_8UC1 or empty: free-space evidence from an older frame (history_evidence): a dynamic
    /// segment or region that the old frame saw but not through is still, not a mover.
    cv::Mat history;
    /// Optional producers of `carried` and `history` when those are empty: called only when a
    /// frame gets as far as growing segments (most frames stop at the guards before), and then
    /// with the pixels whose value can change the outcome (CV_8UC1, non-zero = needed: the
    /// segments whose evidence is between the two fractions, the candidates a history can
    /// keep still), so the projections cost little on frames with motion and nothing without.
    /// Outside `needed` what they return is not read.
    std::function<cv::Mat(const cv::Mat& needed)> carried_source;
    std::function<cv::Mat(const cv::Mat& needed)> history_source;
    /// Optional: an older frame's free space that the current frame fills (free_space_filled;
    /// CV_8UC1, non-zero = filled), called on every frame with the pixels that can count (those
    /// not excluded). Filled pixels are dynamic, whatever their residual.
    std::function<cv::Mat(const cv::Mat& candidates)> filled_source;
};

struct MotionResult {
    cv::Mat mask;             ///< CV_8UC1, 255 = dynamic (unknown mover)
    TwoMeans clusters;        ///< of the clipped residuals
    bool moving = false;      ///< false: the guards found no motion (mask all 0)
    int residual_pixels = 0;  ///< pixels clustered
    int dynamic_pixels = 0;   ///< above the split and the noise floor, before growing
    int segments = 0;         ///< geometric segments (or regions) made dynamic
    int mask_pixels = 0;      ///< non-zero pixels of `mask`
    int still_segments = 0;   ///< segments or regions dynamic by residual, but still by history
    int filled_pixels = 0;    ///< pixels that fill an older frame's free space (dynamic)
    /// Intensity change that counted as evidence this frame (0..255; 0 when the photometric
    /// evidence was off or had no pixels): max(min_photometric, photometric_spread_factor x the
    /// median intensity residual).
    float photometric_threshold = 0.f;
    /// The frame's own residual floor this frame: residual_spread_factor x the median residual
    /// of the pixels clustered (metres; 0 when off).
    float frame_floor_m = 0.f;
};

/// Segments one frame. kInvalidArgument naming the input whose type or size is wrong.
Result<MotionResult> segment_motion(const MotionInput& input,
                                    const MotionSegmentationConfig& config);

}  // namespace df::dynamics
