#pragma once
/// Configuration of the dense surfel SLAM core (DDS-free). Defaults follow ElasticFusion
/// (docs: /work/shared/FACTS.md §5) and suit a 640x480 structured-light or ToF sensor.
#include <string>

#include "params/slam_params.hpp"

namespace df::slam {

/// How one RGB-D image becomes a tracking/fusion `Frame` (see frame.hpp).
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Preprocess), and generated into params/slam_params.hpp.
using PreprocessConfig = params::slam::Preprocess;

/// Empty string when `config` is usable, else a message naming the bad field and its value.
std::string validate(const PreprocessConfig& config);

}  // namespace df::slam
