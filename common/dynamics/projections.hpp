#pragma once
/// The projections motion segmentation reads (docs/dynamics.md): the previous frame's motion
/// mask carried into the current frame by the tracked camera motion (warp_mask), and free-space
/// evidence of an older frame's depth against the current vertices (history_evidence). Both move
/// each current vertex into the other camera and look up what that camera saw there. DDS-free.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>

#include "params/slam_params.hpp"

namespace df::dynamics {

/// history_evidence's codes.
enum HistoryEvidence : uint8_t { kNoEvidence = 0, kStill = 1, kMoved = 2 };

/// `previous` (CV_8UC1 mask of the previous frame) as seen from the current frame: each current
/// pixel with a vertex (CV_32FC3, current camera frame, metres; z <= 0 invalid) is moved into the
/// previous camera by previous_T_current and looks the mask up at its projection (intrinsics fx,
/// fy, cx, cy of both frames). Pixels without a vertex take the previous mask at the same pixel.
/// With `needed` (CV_8UC1 of the vertex map's size) only its non-zero pixels are looked up,
/// the rest are 0.
cv::Mat warp_mask(const cv::Mat& previous, const cv::Mat& vertex,
                  const Eigen::Isometry3f& previous_T_current, float fx, float fy, float cx,
                  float cy, const cv::Mat& needed = cv::Mat());

/// Free-space evidence against an older frame, per pixel of the current one (CV_8UC1): each
/// current vertex (CV_32FC3, current camera frame, metres; z <= 0 invalid) is moved into the old
/// camera by old_T_current and projected (intrinsics of both frames); the old depth there
/// (CV_32F, metres, 0 = none), against the point's own depth in the old camera, gives kMoved when
/// farther by more than history_split |residual| (at least min_residual_m; where `residual_m`
/// (CV_32F, may be empty) has no finite value, the noise floor min_residual_m +
/// min_residual_per_m2 z^2): the old frame saw through the point, towards the surface the map
/// has behind it; kStill when within that and the old frame left the pixel out as a rigid
/// instance (`old_rigid`, CV_8UC1; empty: wherever it was): something a detection kept out of
/// the map, which stood still; else kNoEvidence (nearer: occluded then; missing; outside the old
/// frame; still, but not an instance then, such as a mover that pauses, which stays a mover).
/// With `needed` (CV_8UC1 of the vertex map's size) only its non-zero pixels are evaluated, the
/// rest are kNoEvidence.
cv::Mat history_evidence(const cv::Mat& vertex, const cv::Mat& residual_m, const cv::Mat& old_depth,
                         const cv::Mat& old_rigid, const Eigen::Isometry3f& old_T_current, float fx,
                         float fy, float cx, float cy, const params::slam::Motion& config,
                         const cv::Mat& needed = cv::Mat());

/// Free space filled, per pixel of the current frame (CV_8UC1, 255 where filled, else 0),
/// tested on a grid of seen_through_step_px (a filled sample fills its step x step block): each
/// current vertex (CV_32FC3, current camera frame, metres; z <= 0 invalid) moved into the old
/// camera by old_T_current projects where the old depth (CV_32F, metres, 0 = none) at every
/// pixel of the 3x3 neighbourhood is farther than the point by more than seen_through_margin_m
/// + seen_through_margin_per_m2 z^2: the old frame saw through where the surface is now. Only
/// pixels where `candidates` (CV_8UC1 of the vertex map's size, or empty: all) is non-zero are
/// tested or filled.
cv::Mat free_space_filled(const cv::Mat& vertex, const cv::Mat& old_depth,
                          const Eigen::Isometry3f& old_T_current, float fx, float fy, float cx,
                          float cy, const params::slam::Motion& config,
                          const cv::Mat& candidates = cv::Mat());

}  // namespace df::dynamics
