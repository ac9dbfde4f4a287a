#pragma once
/// Every threshold of the SLAM system in one struct: preprocessing, tracking, surfel map, model
/// prediction, the system's own choices, the dynamics and the object maps. Each is declared once,
/// with its default, range, unit and meaning, in common/config/slam.proto (the section structs
/// are generated from it); `parameters()` (parameters.hpp) lists them all by name for
/// configuration files, flags and `df_slam params`.
#include <string>

#include <vector>

#include "dynamics/instance_memory.hpp"
#include "dynamics/instance_propagation.hpp"
#include "dynamics/invalid_mask.hpp"
#include "dynamics/motion_segmentation.hpp"
#include "map/surfel_map.hpp"
#include "objects/object_maps.hpp"
#include "slam/slam_config.hpp"
#include "slam/tracker.hpp"
#include "params/slam_params.hpp"

namespace df::slam {

/// Choices of the system that are not those of one algorithm.
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.System), and generated into params/slam_params.hpp.
using SystemOptions = params::slam::System;

/// How the static map is kept static (docs/dynamics.md): which masks the frame's pixels are
/// left out by, and the two tracking stages.
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Dynamics), and generated into params/slam_params.hpp.
struct DynamicsOptions : params::slam::Dynamics {
    dynamics::MotionSegmentationConfig motion;
    dynamics::InvalidMaskConfig invalid;
    /// Rigid instances remembered over the frames the detector misses (when invalid.rigid).
    dynamics::InstanceMemoryConfig memory;
    /// Instances carried forward over frames without fresh detections.
    dynamics::PropagationConfig propagation;
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
