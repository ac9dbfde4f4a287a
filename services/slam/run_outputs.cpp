#include "run_outputs.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "eval/stats.hpp"
#include "eval/timing.hpp"

namespace df::slam_service {

StageFigures figures(const std::vector<double>& values_ms) {
    if (values_ms.empty()) return {};
    return {eval::percentile(values_ms, 50), eval::percentile(values_ms, 95)};
}

Result<RunOutputs> RunOutputs::open(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        return error(StatusCode::kIoError,
                     "cannot create the output folder '" + dir + "': " + ec.message());
    }
    const std::string file = dir + "/timings.log";
    std::FILE* f = std::fopen(file.c_str(), "w");
    if (f == nullptr) {
        return error(StatusCode::kIoError, "cannot write '" + file + "'");
    }
    return RunOutputs(dir, f);
}

RunOutputs::RunOutputs(std::string dir, std::FILE* timings)
    : dir_(std::move(dir)), timings_(timings, [](std::FILE* f) { std::fclose(f); }) {}

void RunOutputs::add(uint64_t seq, const slam::FrameReport& report) {
    const slam::StageTimes& t = report.times;
    const std::string line =
        eval::format_timing_line(static_cast<int64_t>(seq), "slam", t.steps()) + "\n";
    std::fputs(line.c_str(), timings_.get());
    preprocess_ms_.push_back(t.preprocess_ms);
    if (!report.first) tracking_ms_.push_back(t.tracking_ms);
    if (report.fused) {
        fusion_ms_.push_back(t.fusion_ms);
        prediction_ms_.push_back(t.prediction_ms);
        if (frames_ % 10 == 0) map_growth_.push_back({frames_, report.fusion.total});
    }
    total_ms_.push_back(t.total_ms);
    ++frames_;
}

Status RunOutputs::finish(const slam::SlamSystem& system, bool stable_only, double wall_s) const {
    std::fflush(timings_.get());
    Status first = system.write_trajectory(trajectory_file());
    Status map = system.write_map(map_file(), stable_only);
    if (first.is_ok()) first = map;

    const map::SurfelMap& m = system.static_map();
    std::ostringstream j;
    j << "{\n  \"frames\": " << system.frames() << ",\n  \"tracked\": "
      << system.trajectory().size() << ",\n  \"lost\": " << system.lost_frames()
      << ",\n  \"wall_s\": " << wall_s << ",\n  \"fps\": "
      << (wall_s > 0 ? static_cast<double>(system.frames()) / wall_s : 0.0)
      << ",\n  \"stages_ms\": {";
    const std::pair<const char*, const std::vector<double>*> stages[] = {
        {"preprocess", &preprocess_ms_}, {"tracking", &tracking_ms_},
        {"fusion", &fusion_ms_},         {"prediction", &prediction_ms_},
        {"total", &total_ms_}};
    bool comma = false;
    for (const auto& [name, values] : stages) {
        const StageFigures f = figures(*values);
        j << (comma ? "," : "") << "\n    \"" << name << "\": {\"median\": " << f.median_ms
          << ", \"p95\": " << f.p95_ms << ", \"count\": " << values->size() << "}";
        comma = true;
    }
    j << "\n  },\n  \"surfels\": " << m.size() << ",\n  \"stable_surfels\": " << m.stable_count()
      << ",\n  \"map_bytes\": " << m.size() * sizeof(map::Surfel)
      << ",\n  \"surfels_rejected_by_capacity\": " << m.total_rejected_by_capacity()
      << ",\n  \"map_growth\": [";
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
