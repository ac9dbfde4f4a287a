#pragma once
/// Frame-to-model camera tracking as ElasticFusion does it: Gauss-Newton on the sum of a
/// geometric term (projective data association, point-to-plane ICP) and a photometric term
/// (intensity of the model's predicted colour against the current image), coarse to fine over
/// the frame's pyramid. DDS-free; the caller owns maps and poses.
///
/// Conventions: poses are world_T_camera (camera x right, y down, z forward, metres). The model
/// view is what the map predicts at a reference pose (usually the previous frame's estimate),
/// expressed in that reference camera's frame.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "slam/frame.hpp"
#include "params/slam_params.hpp"

namespace df::slam {

/// Every threshold of the tracker. Defaults from ElasticFusion (FACTS.md §5) unless noted.
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Tracking), and generated into params/slam_params.hpp.
using TrackingConfig = params::slam::Tracking;

/// Empty string when `config` is usable, else a message naming the bad field and its value.
std::string validate(const TrackingConfig& config);

/// The model as the map predicts it at the reference pose, at full (level 0) resolution.
/// All images have the frame's level-0 size.
struct ModelView {
    /// CV_32FC3, reference camera frame, metres; (0,0,0) where the model has no surface.
    cv::Mat vertex;
    /// CV_32FC3, reference camera frame, unit, towards the camera; (0,0,0) where none.
    cv::Mat normal;
    /// CV_8UC3 R,G,B predicted colour; used by the photometric term (may be empty when
    /// TrackingConfig::use_rgb is false).
    cv::Mat colour;
};

enum class TrackingState {
    kOk,    ///< the estimate passed every check
    kLost,  ///< a check failed; `world_T_camera` is the initial guess, not to be fused
};
const char* to_string(TrackingState state);

/// Per frame: the estimate and how good it is.
struct TrackingResult {
    TrackingState state = TrackingState::kLost;
    /// Why the state is kLost ("" when kOk): which check failed, with the figures.
    std::string reason;
    /// The estimate (kOk) or the initial guess (kLost).
    Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();
    /// What Gauss-Newton converged to, also when a check rejected it (kLost): a two-stage
    /// tracker computes its residuals there (moving objects can fail the inlier checks).
    Eigen::Isometry3d estimate = Eigen::Isometry3d::Identity();
    /// Figures at the finest level tracked, after the last iteration.
    float inlier_ratio = 0.f;  ///< agreeing correspondences / valid frame pixels landing on the
                               ///< model (tracking.inlier_residual_m)
    int inliers = 0;           ///< ICP inliers
    float icp_rmse_m = 0.f;    ///< RMS point-to-plane residual of the inliers
    float rgb_rmse = 0.f;      ///< RMS photometric residual of the pixels used (0 if none)
    int rgb_pixels = 0;        ///< pixels used by the photometric term
    double condition = 0.0;    ///< smallest / largest eigenvalue of the last 6x6 system
    int iterations = 0;        ///< Gauss-Newton iterations run, all levels
};

/// Tracks `frame` against `model`.
/// - world_T_reference: the pose `model` was predicted at.
/// - initial_world_T_camera: the starting estimate (usually world_T_reference).
/// - mask: empty, or CV_8UC1 of the frame's level-0 size; non-zero pixels are left out of both
///   terms (dynamic objects, people).
/// kInvalidArgument naming the bad input (config, image types or sizes); a frame that cannot be
/// tracked is not an error but a kLost result.
Result<TrackingResult> track(const Frame& frame, const ModelView& model,
                             const Eigen::Isometry3d& world_T_reference,
                             const Eigen::Isometry3d& initial_world_T_camera, const cv::Mat& mask,
                             const TrackingConfig& config);

/// Per-pixel geometric residual of `frame` (level 0) against `model` (predicted at
/// world_T_reference) with the frame at world_T_camera: what motion segmentation clusters.
/// CV_32F of the frame's level-0 size, metres, signed: |point-to-plane distance| to the model
/// vertex the pixel projects onto when their normals agree (TrackingConfig::icp_max_normal_sin),
/// else the point-to-point distance; positive when the frame's point is farther from the camera
/// than the model's (the frame sees through the model), negative when nearer. NaN where there
/// is no residual: no valid frame vertex or normal, no model there, or beyond
/// TrackingConfig::max_depth_m. kInvalidArgument as track() for bad inputs.
/// `photometric` (optional): CV_32F, |frame intensity - model intensity| (0..255) at the same
/// association, NaN where there is no residual or the model has no colour.
Result<cv::Mat> residual_image(const Frame& frame, const ModelView& model,
                               const Eigen::Isometry3d& world_T_reference,
                               const Eigen::Isometry3d& world_T_camera,
                               const TrackingConfig& config, cv::Mat* photometric = nullptr);

}  // namespace df::slam
