#pragma once
/// What a SLAM run leaves behind, shared by the offline command and the service:
///   <dir>/trajectory.txt  TUM trajectory of the tracked frames: appended (and flushed) one line
///                         per tracked frame as the run goes, rewritten whole by finish()
///   <dir>/checkpoint.bin  the SLAM state every checkpoint_s (slam_system/checkpoint.hpp)
///   <dir>/map.ply         the static map (binary PLY: position, normal, colour, radius,
///                         confidence)
///   <dir>/timings.log     one "timing seq=N stage=slam preprocess=.. tracking=.. ..." per frame
///   <dir>/summary.json    frames, lost frames, fps, per-stage median/p95, map size and memory
///   <dir>/objects.json, objects/<id>.txt, objects/<id>.ply  the object maps
///                         (objects/object_io.hpp), when the run made any
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam_service {

class RunOutputs {
  public:
    /// Creates `dir` (and parents). resume: keep trajectory.txt and timings.log and append to
    /// them (a run that goes on from a checkpoint); else both start empty. kIoError naming the
    /// folder or file when it cannot.
    static Result<RunOutputs> open(const std::string& dir, bool resume = false);

    /// Appends one pose to trajectory.txt and flushes it, so a crash loses no estimated pose.
    void append_pose(const io::StampedPose& pose);

    /// Records one frame: appends its timing line, keeps its stage times and map size.
    void add(uint64_t seq, const slam::FrameReport& report);

    /// Writes trajectory, map and summary (wall_s: elapsed time of the run, for fps). Each file
    /// is written even if another failed; the first error is returned.
    Status finish(const slam::SlamSystem& system, bool stable_only, double wall_s) const;

    const std::string& dir() const { return dir_; }
    std::string trajectory_file() const { return dir_ + "/trajectory.txt"; }
    std::string map_file() const { return dir_ + "/map.ply"; }
    std::string summary_file() const { return dir_ + "/summary.json"; }
    std::string checkpoint_file() const { return dir_ + "/checkpoint.bin"; }

  private:
    RunOutputs(std::string dir, std::FILE* timings, std::FILE* trajectory);

    std::string dir_;
    std::shared_ptr<std::FILE> timings_;
    std::shared_ptr<std::FILE> trajectory_;  // O_APPEND: lines land after finish()'s rewrite
    std::vector<double> preprocess_ms_, tracking_ms_, fusion_ms_, prediction_ms_, total_ms_;
    std::vector<double> stage1_ms_, motion_ms_, stage2_ms_;  ///< parts of tracking_ms_
    std::vector<double> objects_ms_;         ///< object maps: prediction, tracking, mapping
    std::vector<double> motion_fraction_;    ///< per frame: flagged / looked-at pixels
    std::vector<double> left_out_fraction_;  ///< per frame: left out of tracking / all pixels
    bool guard_logged_ = false;              ///< a guard's first frame was logged
    struct MapSample {
        uint64_t frame;
        size_t surfels;
    };
    std::vector<MapSample> map_growth_;
    uint64_t frames_ = 0;
    /// Frames by where their instances came from: their own detections, an earlier frame's
    /// boxes, none; of those two, frames with instances carried forward; the oldest carried.
    uint64_t own_detections_ = 0, reused_detections_ = 0, no_detections_ = 0, carried_ = 0;
    int oldest_carried_ = 0;
};

/// "median 12.3 ms, p95 15.0 ms" figures of one stage, as summary.json and logs print them.
struct StageFigures {
    double median_ms = 0, p95_ms = 0;
};
StageFigures figures(const std::vector<double>& values_ms);

/// The COCO name of a class id ("class 91" outside the table).
std::string class_name(int class_id);

}  // namespace df::slam_service
