#pragma once
/// A preprocessed RGB-D frame: per pyramid level depth, vertices, normals, intensity and its
/// gradients, ready for projective ICP + photometric tracking and for surfel fusion.
///
/// Conventions (every level):
/// - Camera frame: x right, y down, z forward (optical axis), metres.
/// - Invalid depth is 0 (never NaN). A pixel whose vertex or normal is invalid holds (0,0,0);
///   test validity with `is_valid_vertex` / `is_valid_normal` below.
#include <opencv2/core.hpp>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "slam/slam_config.hpp"

namespace df::slam {

/// A vertex is valid when it has positive depth.
inline bool is_valid_vertex(const cv::Vec3f& v) { return v[2] > 0.f; }
/// A normal is valid when it is not the (0,0,0) marker (valid normals have unit length).
inline bool is_valid_normal(const cv::Vec3f& n) {
    return n[0] != 0.f || n[1] != 0.f || n[2] != 0.f;
}

struct FrameLevel {
    /// Intrinsics of this level: f / 2^l and (c + 0.5) / 2^l - 0.5, so pixel centres line up.
    io::Intrinsics intrinsics;
    /// CV_32F, metres, 0 = invalid. Level 0: the raw sensor depth after the range cut (what
    /// fusion should use). Level l > 0: discontinuity-aware 2x2 block average of level l - 1.
    cv::Mat depth_m;
    /// CV_32F, metres, 0 = invalid: bilateral-filtered depth (level 0), block-averaged below.
    /// Valid exactly where depth_m is valid.
    cv::Mat smoothed_depth_m;
    /// CV_32FC3, camera frame, metres: back-projection of depth_m; (0,0,0) where invalid.
    cv::Mat vertex;
    /// CV_32FC3, camera frame, metres: back-projection of smoothed_depth_m (what tracking
    /// aligns: less sensor noise); (0,0,0) where invalid.
    cv::Mat smoothed_vertex;
    /// CV_32FC3, unit normals in the camera frame from central differences of the smoothed
    /// vertex map, oriented towards the camera (n . vertex < 0). (0,0,0) where the pixel or one
    /// of its 4 neighbours has no smoothed depth, and on the image border.
    cv::Mat normal;
    /// CV_32F, 0.299 R + 0.587 G + 0.114 B in 0..255 (level 0); Gaussian pyrDown below.
    cv::Mat intensity;
    /// CV_32F, intensity gradient per pixel along x (right) and y (down): Sobel 3x3 / 8, i.e.
    /// intensity units per pixel of this level. Border pixels use reflected neighbours.
    cv::Mat grad_x, grad_y;

    int width() const { return depth_m.cols; }
    int height() const { return depth_m.rows; }
};

struct Frame {
    /// levels[0] is full resolution; levels.size() == PreprocessConfig::pyramid_levels.
    std::vector<FrameLevel> levels;
    int64_t sensor_ns = 0;  ///< copied from the image
    uint64_t index = 0;     ///< copied from the image
    /// Level-0 size of the whole sensor image, also in a crop(): what an observation's weight
    /// (its distance from the principal point against half the image diagonal) refers to.
    cv::Size sensor_size;
};

/// Builds a Frame from an RGB-D image. Needs `image.rgb` CV_8UC3 (R,G,B) and `image.depth`
/// CV_16UC1 of the same size, depth_units_per_m > 0, positive focal lengths, and an image large
/// enough for the requested levels (coarsest level at least 8x8). Fails with kInvalidArgument
/// (naming the bad field) otherwise. Deterministic: the same input gives bit-identical output
/// whatever the number of threads.
Result<Frame> preprocess(const io::RgbdImage& image, const PreprocessConfig& config);

/// The part of `frame` inside `roi` (level-0 pixels): every level cropped alike, its intrinsics
/// shifted so a camera-frame point projects onto the same image content; the images are views
/// into `frame`'s (no copy, valid while they are). `roi` is first grown outwards to multiples of
/// 2^(levels-1) and clipped to the frame, so that every level crops whole pixels; the rectangle
/// used is returned in `*used` (empty when roi does not meet the frame; then the frame returned
/// has empty images). Lets a small object be tracked and fused at the cost of its own size.
Frame crop(const Frame& frame, const cv::Rect& roi, cv::Rect* used);

}  // namespace df::slam
