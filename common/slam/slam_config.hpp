#pragma once
/// Configuration of the dense surfel SLAM core (DDS-free). Defaults follow ElasticFusion
/// (docs: /work/shared/FACTS.md §5) and suit a 640x480 structured-light or ToF sensor.
#include <string>

namespace df::slam {

/// How one RGB-D image becomes a tracking/fusion `Frame` (see frame.hpp).
struct PreprocessConfig {
    /// Depth below this (metres) is invalid: sensors return noise closer than their minimum.
    float min_depth_m = 0.3f;
    /// Depth at or beyond this (metres) is invalid. ElasticFusion cuts at 3 m for everything;
    /// here the map takes depth up to 6 m (the far walls of a room; surfel averaging and the
    /// unstable rule absorb the z^2 noise) and tracking cuts at TrackingConfig::max_depth_m
    /// (3 m), where normals are still precise enough for its normal gate.
    float max_depth_m = 6.0f;

    /// Bilateral filter applied to depth before normals are computed (raw depth is kept for
    /// fusion). Spatial Gaussian sigma in pixels of the finest level.
    float bilateral_sigma_space_px = 4.5f;
    /// Range Gaussian sigma in metres: neighbours further than a few sigma in depth do not count,
    /// which keeps depth discontinuities sharp.
    float bilateral_sigma_depth_m = 0.03f;
    /// Half width of the square filter window in pixels (2 = 5x5 window).
    int bilateral_radius_px = 2;
    /// Normals are central differences of the smoothed vertices this many pixels apart (on
    /// every pyramid level). 1 is ElasticFusion's; a longer baseline divides the angular noise
    /// of far or quantised depth by about that factor (Kinect-like noise grows with z^2).
    int normal_baseline_px = 2;

    /// Number of pyramid levels, level 0 being full resolution; each level halves width/height.
    int pyramid_levels = 3;
    /// When a 2x2 block of depth is averaged into the next level, pixels differing from the
    /// block's reference pixel by more than this (metres) are left out, so depth is not averaged
    /// across discontinuities. Default 3 x bilateral_sigma_depth_m.
    float pyramid_max_depth_diff_m = 0.09f;
};

/// Empty string when `config` is usable, else a message naming the bad field and its value.
std::string validate(const PreprocessConfig& config);

}  // namespace df::slam
