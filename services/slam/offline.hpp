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
    /// "on": geometric segmentation, detection, box-and-segment fusion, motion segmentation,
    /// two-stage tracking (what the pipeline runs); "off": the static core, masks ignored.
    std::string dynamics = "on";
    /// "yolov5" (config.detector()), "simulated" (SIMULATED boxes from the folder's ground
    /// truth: generated sequences only) or "none" (motion segmentation alone).
    std::string detector = "yolov5";
    /// The detector runs on frames 0, N, 2N, ... only; the others get its last boxes with
    /// their age (FrameSegments::detections_age), as the fusion service reuses late boxes.
    int detect_every = 1;
    bool write_masks = true;  ///< per-frame label PNGs (mask_outputs.hpp)
    bool overlay = false;     ///< and overlay pictures
    /// Also write the run's Foxglove views to this MCAP file ("" none; foxglove_output.hpp).
    std::string foxglove;
};

/// Runs to the end of the folder; returns the process exit code (0 ok, 1 failure).
int run_offline(const OfflineOptions& options, const config::SlamServiceConfig& config);

}  // namespace df::slam_service
