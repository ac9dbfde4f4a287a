#pragma once
/// df_slam offline: the SLAM system over a recorded folder in one process (no DDS).
#include <cstdint>
#include <string>
#include <vector>

#include "slam.pb.h"

namespace df::slam_service {

struct OfflineOptions {
    std::string folder;
    std::string out_dir;
    /// Camera preset: "" = the folder's intrinsics.txt when it has one (generated sequences),
    /// else fr3; fr1, fr2, fr3 (TUM, depth 5000/m), 7scenes (depth 1000/m, 65535 invalid).
    std::string preset;
    uint64_t max_frames = 0;  ///< 0 = all
    /// Ground truth for the ATE printed at the end: "" = <folder>/groundtruth.txt if present.
    std::string groundtruth;
};

/// Runs to the end of the folder; returns the process exit code (0 ok, 1 failure).
int run_offline(const OfflineOptions& options, const config::SlamServiceConfig& config);

}  // namespace df::slam_service
