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

namespace df::slam {

/// Every threshold of the tracker. Defaults from ElasticFusion (FACTS.md §5) unless noted.
struct TrackingConfig {
    /// Gauss-Newton iterations per pyramid level, finest (level 0) first. Its size must equal
    /// the number of levels tracked (the frame's pyramid may have more; extra levels unused).
    std::vector<int> iterations = {10, 5, 4};
    /// Pixel step at each level (1 = every pixel, 2 = every other row and column). Lets the
    /// caller trade accuracy for speed at the finest level without a new pyramid.
    std::vector<int> pixel_step = {1, 1, 1};

    // --- geometric term (point-to-plane ICP, projective association) ---
    /// A frame vertex is associated with the model vertex its pose projects onto when the two
    /// are closer than this (metres) ...
    float icp_max_distance_m = 0.10f;
    /// ... and the sine of the angle between their normals is below this (sin 20 deg).
    float icp_max_normal_sin = 0.34202f;

    // --- photometric term ---
    /// Whether the photometric term is used at all (false: ICP only).
    bool use_rgb = true;
    /// Weight w of the ICP term in A = A_rgb + w^2 A_icp, b = b_rgb + w^2 b_icp, i.e. the
    /// Gauss-Newton step of E_rgb + w^2 E_icp, at the finest level tracked. Each term's
    /// residuals are first divided by its Huber threshold (icp_huber_m, rgb_huber) so the two
    /// are commensurable: raw, the photometric normal equations (intensity units) outweigh the
    /// ICP ones (metres) by ~1e4. (ElasticFusion's code scales b_icp by w only; with ICP
    /// dominating that shrinks the step by 1/w in its directions, so w^2 is used on both.)
    /// ElasticFusion's w = 10 counts an ICP pixel 100 times a photometric one in these units;
    /// 1 (equal) at the finest level, with icp_weight_coarse below it, was the most accurate on
    /// every sequence of the study in docs/dynamics.md ("Weighting ICP against intensity").
    float icp_weight = 1.f;
    /// w at the coarser levels: ICP's basin of convergence is wide, the photometric term's is
    /// about one wavelength of the texture, so a fast motion is first brought close by ICP
    /// (a 4 cm, 2.5 deg step over a texture of 8 cm wavelength converged 9 cm off with w = 1 at
    /// every level).
    float icp_weight_coarse = 10.f;
    /// Divide each term by its own residual spread (the Huber-weighted mean square of this
    /// iteration's residuals, floored at a tenth of its threshold) instead of its Huber
    /// threshold squared: the maximum-likelihood weighting of two Gaussian terms. Measured less
    /// accurate than the fixed thresholds with w = 1 (7-Scenes 2.37 against 2.18 cm), so off.
    bool adaptive_weights = false;
    /// Minimum gradient magnitude (intensity units per pixel, Sobel/8) of a pixel used by the
    /// photometric term, per level finest first.
    std::vector<float> rgb_min_gradient = {5.f, 3.f, 1.f};
    /// A model pixel is used by the photometric term only when the frame's depth where it
    /// projects agrees with the model depth within this (metres).
    float rgb_max_depth_difference_m = 0.07f;
    /// Frame and model points farther than this along z (metres) are left out of both terms;
    /// 0 = no limit beyond preprocessing's range cut. Lets the map take in far surfaces (a
    /// larger preprocess.max_depth_m) while tracking uses only depth precise enough for its
    /// normal gate (Kinect-like noise grows with z^2; with 4-6 m of depth in tracking the
    /// default data's inlier ratio fell below 0.5). ElasticFusion's 3 m.
    float max_depth_m = 4.f;

    // --- robust weighting ---
    /// Huber thresholds on the residuals: geometric in metres, photometric in intensity units.
    /// Residuals beyond them get weight threshold / |r| (iteratively reweighted).
    float icp_huber_m = 0.01f;
    float rgb_huber = 10.f;

    // --- convergence and failure ---
    /// An iteration whose update is smaller than both (metres, radians) ends the level early.
    float min_update_translation_m = 1e-5f;
    float min_update_rotation_rad = 1e-5f;
    /// The estimate is rejected (state kLost) when, at the finest level tracked:
    /// - fewer than this fraction of the frame's valid pixels that land on the model (at the
    ///   final estimate) are ICP inliers, or
    float min_inlier_ratio = 0.5f;
    /// - fewer than this fraction of all the frame's valid pixels are ICP inliers (a view that
    ///   barely overlaps the model), or
    float min_frame_inlier_ratio = 0.15f;
    /// - fewer than this many ICP inliers in all, or
    int min_inliers = 500;
    /// - the RMS point-to-plane residual of the inliers exceeds this (metres), or
    float max_icp_rmse_m = 0.03f;
    /// - the ratio of smallest to largest eigenvalue of the 6x6 system is below this
    ///   (degenerate geometry, e.g. a single plane with no texture), or
    double min_condition = 1e-6;
    /// - the estimate moved further than this from the initial guess (metres, radians).
    float max_translation_m = 0.30f;
    float max_rotation_rad = 0.50f;
};

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
    float inlier_ratio = 0.f;  ///< ICP inliers / valid frame pixels landing on the model
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
