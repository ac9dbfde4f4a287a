#pragma once
/// Internal to the tracker (tracker.cpp): the per-level data the Gauss-Newton loop works on and
/// the two accumulation passes (geometric, photometric). Not part of df_slam's public API.
///
/// Twist convention shared by both terms: an increment xi = (t, w) (metres, radians) updates the
/// estimate as reference_T_camera <- Exp(xi) * reference_T_camera, i.e. it moves the camera in
/// the reference frame. Each pass returns A = sum weight J^T J and b = sum weight J^T r, so the
/// step solves A xi = -b.
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "slam/frame.hpp"
#include "slam/tracker.hpp"

namespace df::slam::tracker_detail {

/// Normal equations of one pass: the 21 upper-triangle entries of the 6x6 A (row by row), b,
/// and what the pass saw.
struct NormalEquations {
    std::array<double, 21> a{};
    std::array<double, 6> b{};
    double residual_sq = 0.0;  ///< sum of the unweighted squared residuals of the pixels used
    double weighted_sq = 0.0;  ///< sum of their Huber-weighted squares (w r^2: outliers count |r|)
    int used = 0;              ///< pixels that contributed (ICP: inliers)
    int agreeing = 0;          ///< ICP: correspondences agreeing, whatever the normals' angle

    void add(const NormalEquations& other);
};

/// A rigid transform in float for the inner loops: x' = r x + t, r row-major.
struct PoseF {
    float r[9];
    float t[3];
};

/// One level of the model's pyramid, in the reference camera frame.
struct ModelLevel {
    cv::Mat vertex;     ///< CV_32FC3, (0,0,0) where none
    cv::Mat normal;     ///< CV_32FC3, (0,0,0) where none
    cv::Mat intensity;  ///< CV_32F, 0..255; negative where the photometric term cannot use it
};

/// The model's pyramid, `levels` levels, sizes halving (floor) like the frame's. Vertices and
/// normals of level l > 0 average the 2x2 block pixels within a depth tolerance of the block's
/// first valid pixel; intensity is 0.299 R + 0.587 G + 0.114 B, then Gaussian pyrDown (as the
/// frame's) normalised by the valid pixels, and unusable where any of its support is invalid.
/// Needs use_rgb only for intensity (left empty when `with_intensity` is false).
std::vector<ModelLevel> build_model_pyramid(const ModelView& model, int levels,
                                            bool with_intensity);

/// Mask pyramid: a pixel of level l > 0 is masked when any pixel of its 2x2 block is. Empty
/// matrices when `mask` is empty.
std::vector<cv::Mat> build_mask_pyramid(const cv::Mat& mask, int levels);

/// Point-to-plane ICP with projective association into the model at `k` (nearest pixel).
/// `reference_T_camera` is the current estimate.
/// Frame pixels used: valid vertex and normal, not masked (`mask` may be empty), on the `step`
/// grid. `valid` returns how many such pixels there are.
NormalEquations accumulate_icp(const FrameLevel& frame, const cv::Mat& mask, int step,
                               const ModelLevel& model, const PoseF& reference_T_camera,
                               const TrackingConfig& config, int& valid);

/// Photometric term: model points warped into the current frame (`camera_T_reference`),
/// residual I_frame(pi(p')) - I_model, for model pixels with a vertex and usable intensity on
/// the `step` grid. `reference_T_camera` is the estimate, `camera_T_reference` its inverse.
NormalEquations accumulate_rgb(const ModelLevel& model, int step, const FrameLevel& frame,
                               const cv::Mat& mask, const PoseF& camera_T_reference,
                               const PoseF& reference_T_camera, float min_gradient,
                               const TrackingConfig& config);

}  // namespace df::slam::tracker_detail
