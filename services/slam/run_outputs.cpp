#include "run_outputs.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "core/log.hpp"
#include "detect/detector.hpp"
#include "eval/stats.hpp"
#include "eval/timing.hpp"
#include "objects/object_io.hpp"

namespace df::slam_service {

std::string class_name(int class_id) {
    const auto& names = detect::coco_names();
    if (class_id < 0) return "unknown";  // an unknown mover's map (objects.from_motion)
    return class_id < static_cast<int>(names.size()) ? names[static_cast<size_t>(class_id)]
                                                     : "class " + std::to_string(class_id);
}

StageFigures figures(const std::vector<double>& values_ms) {
    if (values_ms.empty()) return {};
    return {eval::percentile(values_ms, 50), eval::percentile(values_ms, 95)};
}

Result<RunOutputs> RunOutputs::open(const std::string& dir, bool resume) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        return error(StatusCode::kIoError,
                     "cannot create the output folder '" + dir + "': " + ec.message());
    }
    const char* mode = resume ? "a" : "w";
    const std::string file = dir + "/timings.log";
    std::FILE* f = std::fopen(file.c_str(), mode);
    if (f == nullptr) {
        return error(StatusCode::kIoError, "cannot write '" + file + "'");
    }
    const std::string traj = dir + "/trajectory.txt";
    if (!resume) {
        if (std::FILE* empty = std::fopen(traj.c_str(), "w")) std::fclose(empty);
    }
    // Append mode (O_APPEND): each line lands at the end, also after finish() rewrote the file.
    std::FILE* t = std::fopen(traj.c_str(), "a");
    if (t == nullptr) {
        std::fclose(f);
        return error(StatusCode::kIoError, "cannot append to '" + traj + "'");
    }
    return RunOutputs(dir, f, t);
}

RunOutputs::RunOutputs(std::string dir, std::FILE* timings, std::FILE* trajectory)
    : dir_(std::move(dir)),
      timings_(timings, [](std::FILE* f) { std::fclose(f); }),
      trajectory_(trajectory, [](std::FILE* f) { std::fclose(f); }) {}

void RunOutputs::append_pose(const io::StampedPose& p) {
    // The line format of io::write_tum_trajectory, so the appended file reads back the same.
    const Eigen::Quaterniond q = p.q.normalized();
    std::fprintf(trajectory_.get(), "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.stamp_s,
                 p.t.x() + 0.0, p.t.y() + 0.0, p.t.z() + 0.0, q.x() + 0.0, q.y() + 0.0, q.z() + 0.0,
                 q.w() + 0.0);
    std::fflush(trajectory_.get());
}

void RunOutputs::add(uint64_t seq, const slam::FrameReport& report) {
    const slam::StageTimes& t = report.times;
    const std::string line =
        eval::format_timing_line(static_cast<int64_t>(seq), "slam", t.steps()) + "\n";
    std::fputs(line.c_str(), timings_.get());
    preprocess_ms_.push_back(t.preprocess_ms);
    if (!report.first) {
        tracking_ms_.push_back(t.tracking_ms);
        stage1_ms_.push_back(t.stage1_ms);
        motion_ms_.push_back(t.motion_ms);
        stage2_ms_.push_back(t.stage2_ms);
        // Of the pixels motion segmentation looked at (a depth and a model point, not an
        // instance left out), the fraction it flagged as moving.
        if (report.motion.residual_pixels > 0)
            motion_fraction_.push_back(static_cast<double>(report.motion.mask_pixels) /
                                       report.motion.residual_pixels);
    }
    if (!report.invalid.tracking.empty())
        left_out_fraction_.push_back(
            static_cast<double>(cv::countNonZero(report.invalid.tracking)) /
            static_cast<double>(report.invalid.tracking.total()));
    else
        left_out_fraction_.push_back(0.0);
    if (!report.guard.empty() && !guard_logged_) {
        log::warn("seq=", seq, " guard: ", report.guard,
                  "; tracked and fused with only persons left out (logged once; summary.json "
                  "counts such frames)");
        guard_logged_ = true;
    }
    if (!report.rebuilt.empty())
        log::warn("seq=", seq, " static map rebuilt: ", report.rebuilt,
                  "; the trajectory goes on from the last tracked pose in a new segment");
    for (const objects::ObjectReport& o : report.objects)
        if (o.mover_changed)
            log::info("seq=", seq, " object ", o.id,
                      o.moving ? " moves: left out of the static map"
                               : " stands still again: back in the static map");
    if (report.fused) {
        fusion_ms_.push_back(t.fusion_ms);
        prediction_ms_.push_back(t.prediction_ms);
        if (frames_ % 10 == 0) map_growth_.push_back({frames_, report.fusion.total});
    }
    if (report.detections_age == 0)
        ++own_detections_;
    else if (report.detections_age > 0)
        ++reused_detections_;
    else
        ++no_detections_;
    if (report.carried > 0) {
        ++carried_;
        for (const dynamics::InstanceInfo& row : report.instances.instances)
            oldest_carried_ = std::max(oldest_carried_, row.age);
    }
    total_ms_.push_back(t.total_ms);
    objects_ms_.push_back(t.objects_predict_ms + t.objects_track_ms + t.objects_map_ms);
    ++frames_;
}

Status RunOutputs::finish(const slam::SlamSystem& system, bool stable_only, double wall_s) const {
    std::fflush(timings_.get());
    Status first = system.write_trajectory(trajectory_file());
    Status map = system.write_map(map_file(), stable_only);
    if (first.is_ok()) first = map;
    if (!system.object_maps().objects().empty()) {
        Status objects =
            objects::write_objects(dir_, system.object_maps(), class_name, stable_only);
        if (first.is_ok()) first = objects;
    }

    const map::SurfelMap& m = system.static_map();
    std::ostringstream j;
    j << "{\n  \"frames\": " << system.frames()
      << ",\n  \"tracked\": " << system.trajectory().size()
      << ",\n  \"lost\": " << system.lost_frames() << ",\n  \"wall_s\": " << wall_s
      << ",\n  \"fps\": " << (wall_s > 0 ? static_cast<double>(system.frames()) / wall_s : 0.0)
      << ",\n  \"stages_ms\": {";
    const std::pair<const char*, const std::vector<double>*> stages[] = {
        {"preprocess", &preprocess_ms_}, {"tracking", &tracking_ms_},     {"stage1", &stage1_ms_},
        {"motion", &motion_ms_},         {"stage2", &stage2_ms_},         {"objects", &objects_ms_},
        {"fusion", &fusion_ms_},         {"prediction", &prediction_ms_}, {"total", &total_ms_}};
    bool comma = false;
    for (const auto& [name, values] : stages) {
        const StageFigures f = figures(*values);
        j << (comma ? "," : "") << "\n    \"" << name << "\": {\"median\": " << f.median_ms
          << ", \"p95\": " << f.p95_ms << ", \"count\": " << values->size() << "}";
        comma = true;
    }
    double fraction_sum = 0, fraction_max = 0;
    size_t flagged = 0;
    for (double f : motion_fraction_) {
        fraction_sum += f;
        fraction_max = std::max(fraction_max, f);
        flagged += f > 0;
    }
    j << "\n  },\n  \"motion_fraction\": {\"mean\": "
      << (motion_fraction_.empty() ? 0.0 : fraction_sum / motion_fraction_.size())
      << ", \"max\": " << fraction_max << ", \"frames_flagged\": " << flagged
      << ", \"frames\": " << motion_fraction_.size() << "}";
    double left_sum = 0, left_max = 0;
    for (double f : left_out_fraction_) {
        left_sum += f;
        left_max = std::max(left_max, f);
    }
    j << ",\n  \"left_out_fraction\": {\"mean\": "
      << (left_out_fraction_.empty() ? 0.0 : left_sum / left_out_fraction_.size())
      << ", \"max\": " << left_max << "}";
    const slam::GuardCounters& g = system.guards();
    j << ",\n  \"guards\": {\"frames_guarded\": " << g.frames_guarded
      << ", \"rebuilds\": " << g.rebuilds << ", \"segment_starts\": [";
    for (size_t i = 0; i < g.segment_starts.size(); ++i)
        j << (i ? ", " : "") << g.segment_starts[i];
    j << "]}";
    // Masks for every frame (docs/dynamics.md, "Masks for every frame"): this run's frames by
    // the age of their detections, and those that got instances carried forward.
    j << ",\n  \"masks\": {\"own_detections\": " << own_detections_
      << ", \"reused_detections\": " << reused_detections_
      << ", \"no_detections\": " << no_detections_ << ", \"carried\": " << carried_
      << ", \"oldest_carried_frames\": " << oldest_carried_ << "}";
    j << ",\n  \"surfels\": " << m.size() << ",\n  \"stable_surfels\": " << m.stable_count()
      << ",\n  \"map_bytes\": " << m.size() * sizeof(map::Surfel)
      << ",\n  \"surfels_rejected_by_capacity\": " << m.total_rejected_by_capacity()
      << ",\n  \"objects\": " << system.object_maps().objects().size() << ",\n  \"map_growth\": [";
    for (size_t i = 0; i < map_growth_.size(); ++i) {
        j << (i ? ", " : "") << "[" << map_growth_[i].frame << ", " << map_growth_[i].surfels
          << "]";
    }
    j << "]\n}\n";
    std::ofstream out(summary_file());
    out << j.str();
    if (!out) {
        const Status s(StatusCode::kIoError, "cannot write '" + summary_file() + "'");
        if (first.is_ok()) first = s;
    }
    return first;
}

}  // namespace df::slam_service
