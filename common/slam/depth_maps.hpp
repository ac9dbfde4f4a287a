#pragma once
/// The building blocks of `preprocess` (frame.hpp), exposed for tests and for tools that need
/// one step alone. All depth images are CV_32F in metres with 0 = invalid.
#include <opencv2/core.hpp>

#include "io/rgbd_image.hpp"

namespace df::slam {

/// Raw CV_16UC1 depth -> CV_32F metres; values outside [min_depth_m, max_depth_m) become 0.
cv::Mat depth_to_metres(const cv::Mat& raw_depth, double units_per_m, float min_depth_m,
                        float max_depth_m);

/// Edge-preserving bilateral filter over a (2 radius + 1)^2 window: weights
/// exp(-d_px^2 / 2 sigma_space^2) * exp(-dz^2 / 2 sigma_depth^2) over valid neighbours only.
/// Invalid pixels stay invalid; valid pixels stay valid. Neighbours more than 4 sigma_depth away
/// in depth get weight 0. The range weight is evaluated to a relative error below 4e-6, so results
/// agree with a double-precision std::exp evaluation to float rounding (~1e-6 m). Parallel over
/// rows, SIMD (AVX2 where the CPU has it, same bits either way), deterministic whatever the
/// thread count.
cv::Mat bilateral_filter_depth(const cv::Mat& depth_m, float sigma_space_px, float sigma_depth_m,
                               int radius_px);

/// Next pyramid level of a depth image, size (cols / 2, rows / 2): each output pixel averages the
/// valid pixels of its 2x2 block that lie within max_diff_m of the block's reference pixel (the
/// first valid pixel in the order top-left, top-right, bottom-left, bottom-right). Invalid when
/// the block has no valid pixel.
cv::Mat downsample_depth(const cv::Mat& depth_m, float max_diff_m);

/// Intrinsics of pyramid level `level` (0 = unchanged): f / 2^l, (c + 0.5) / 2^l - 0.5.
io::Intrinsics scale_intrinsics(const io::Intrinsics& k, int level);

/// CV_32FC3 back-projection ((u - cx) z / fx, (v - cy) z / fy, z); (0,0,0) where depth is 0.
cv::Mat compute_vertex_map(const cv::Mat& depth_m, const io::Intrinsics& k);

/// CV_32FC3 unit normals from central differences of `vertex` ((x+b) - (x-b) crossed with
/// (y+b) - (y-b), b = baseline_px >= 1), oriented so that n . vertex < 0 (towards the camera).
/// (0,0,0) on the b-pixel border and where the pixel or one of its 4 neighbours is invalid.
cv::Mat compute_normal_map(const cv::Mat& vertex, int baseline_px = 1);

/// compute_normal_map(compute_vertex_map(depth_m, k), baseline_px), bit for bit, without the
/// intermediate vertex map.
cv::Mat compute_normal_map(const cv::Mat& depth_m, const io::Intrinsics& k, int baseline_px = 1);

/// CV_32F intensity 0.299 R + 0.587 G + 0.114 B (0..255) of a CV_8UC3 R,G,B image.
cv::Mat rgb_to_intensity(const cv::Mat& rgb);

}  // namespace df::slam
