#pragma once
/// Every threshold of the static-scene SLAM system in one struct: preprocessing, tracking,
/// surfel map, model prediction and the system's own choices. Units and defaults are documented
/// where each field is declared; `parameters()` (parameters.hpp) lists them all by name for
/// configuration files, flags and `df_slam params`.
#include <string>

#include "map/surfel_map.hpp"
#include "slam/slam_config.hpp"
#include "slam/tracker.hpp"

namespace df::slam {

/// Choices of the system that are not those of one algorithm.
struct SystemOptions {
    /// 1: process the input at its own resolution; 2: halve width and height first (depth by
    /// nearest neighbour, so no depth is averaged across edges; colour by area averaging), which
    /// makes every stage about 4x cheaper at some cost in accuracy. Default 2: on this project's
    /// 2-core reference machine it is the resolution that keeps tracking + mapping within 50 ms
    /// per frame (docs/benchmarks.md); use 1 where a faster CPU allows.
    int processing_downscale = 2;
    /// The model tracking aligns to renders surfels with confidence >= this (ElasticFusion
    /// tracks against its confident surfels: fresh, noisy ones would pull the pose) ...
    float predict_min_confidence = 0.f;
    /// ... except during the first this many frames, when every active surfel is rendered (no
    /// surfel can be confident yet).
    int bootstrap_frames = 5;
    /// Initial guess of each frame's pose: false = the previous pose (ElasticFusion); true =
    /// the previous pose moved on by the last frame-to-frame motion (constant velocity).
    bool constant_velocity = false;
    /// Fuse frames whose tracking is lost (false keeps a wrong pose out of the map).
    bool fuse_when_lost = false;
    /// Fusion associates each pixel with the surfel a prediction of every active surfel at the
    /// new pose shows there (true), or with the nearest surfel centre projected into it (false,
    /// cheaper: no second rendering).
    bool associate_by_prediction = true;
};

struct SystemConfig {
    PreprocessConfig preprocess;
    TrackingConfig tracking;
    map::SurfelMapConfig map;
    map::PredictionConfig prediction;
    SystemOptions system;
};

/// Empty string when usable, else a message naming the bad field and its value.
std::string validate(const SystemConfig& config);

}  // namespace df::slam
