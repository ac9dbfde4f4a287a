#pragma once
/// Every threshold of the static-scene SLAM system in one struct: preprocessing, tracking,
/// surfel map, model prediction and the system's own choices. Units and defaults are documented
/// where each field is declared; `parameters()` (parameters.hpp) lists them all by name for
/// configuration files, flags and `df_slam params`.
#include <string>

#include <vector>

#include "dynamics/instance_memory.hpp"
#include "dynamics/invalid_mask.hpp"
#include "dynamics/motion_segmentation.hpp"
#include "map/surfel_map.hpp"
#include "objects/object_maps.hpp"
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
    /// 3: fragments of a mover fused in a frame or two (a missed detection) do not show in the
    /// model, so they neither pull tracking nor hide the mover from motion segmentation (its
    /// residuals are then against the background behind it); 7-Scenes ATE unchanged (2.42 cm
    /// with 0 or 3, docs/dynamics.md).
    float predict_min_confidence = 3.f;
    /// ... except during the first this many frames, when every active surfel is rendered (no
    /// surfel can be confident yet).
    int bootstrap_frames = 10;
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

/// How the static map is kept static (docs/dynamics.md): which masks the frame's pixels are
/// left out by, and the two tracking stages.
struct DynamicsOptions {
    /// Leave the frame's object instances (FrameSegments::objects, of the kinds `invalid`
    /// names) out of tracking and fusion of the static map. false: segments are ignored.
    bool use_segments = true;
    /// Find unknown movers in stage 1's residuals and leave them out too (stage 2).
    bool motion_segmentation = true;
    /// Motion segments of the previous frame, warped by the tracked motion, lower the evidence
    /// a segment needs to stay dynamic (MotionSegmentationConfig::carried_segment_fraction).
    bool carry_forward = true;
    /// Gauss-Newton iterations per level (finest first) of stage 2, the refinement of stage 1's
    /// pose with the whole invalid mask left out; run only when motion segmentation found
    /// something. Its size must be that of tracking.iterations.
    std::vector<int> refine_iterations = {6, 3, 0};
    /// A frame stage 1 rejected is rescued by stage 2 only when motion segmentation left out at
    /// most this fraction of the pixels it clustered: a wrong pose makes everything look like it
    /// moved, and a mask that explains away most of the view would pass any check.
    float max_rescue_fraction = 0.3f;
    dynamics::MotionSegmentationConfig motion;
    dynamics::InvalidMaskConfig invalid;
    /// Rigid instances remembered over the frames the detector misses (when invalid.rigid).
    dynamics::InstanceMemoryConfig memory;
};

struct SystemConfig {
    PreprocessConfig preprocess;
    TrackingConfig tracking;
    map::SurfelMapConfig map;
    map::PredictionConfig prediction;
    SystemOptions system;
    DynamicsOptions dynamics;
    /// Object maps for rigid objects (objects/object_maps.hpp); their tracking and surfels use
    /// `tracking` and `map` with the few thresholds of their own listed there.
    objects::ObjectMapsConfig objects;
};

/// Empty string when usable, else a message naming the bad field and its value.
std::string validate(const SystemConfig& config);

}  // namespace df::slam
