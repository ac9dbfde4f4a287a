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
    /// Folder of per-frame masks "<stamp>.png" (stamp of the colour image, 6 decimals, as the
    /// TUM lists and df_make_sequence's instances/ name them), 8- or 16-bit, any non-zero pixel
    /// left out of tracking and fusion. "" = no masks. With a generated sequence's instances/
    /// this is ground-truth (simulated) segmentation, an upper bound for issue 5's masks.
    std::string masks;
    int mask_dilate_px = 2;  ///< masks grown by this many pixels (object rims have mixed depth)
};

/// Runs to the end of the folder; returns the process exit code (0 ok, 1 failure).
int run_offline(const OfflineOptions& options, const config::SlamServiceConfig& config);

}  // namespace df::slam_service
