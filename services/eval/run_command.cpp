// df_eval run SEQ_DIR RUN_DIR: score whatever a run folder holds, write eval.json and figures.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "commands.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "eval/plots.hpp"
#include "eval/report.hpp"
#include "eval/timing.hpp"
#include "io/ply/ply.hpp"

namespace df::eval_cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// What one `run` collects: the JSON document, the problems, and what was not there to score.
struct RunReport {
    json doc = json::object();
    std::vector<std::string> errors;
    std::vector<std::string> skipped;
    void fail(const std::string& what, const Status& s) {
        errors.push_back(what + ": " + s.message());
        log::error(errors.back());
    }
    void fail(const std::string& text) {
        errors.push_back(text);
        log::error(errors.back());
    }
    void skip(const std::string& why) {
        skipped.push_back(why);
        log::info("skipped: ", why);
    }
};

bool file_exists(const fs::path& p) {
    std::error_code ec;
    return fs::exists(p, ec);
}

void plot(RunReport* report, const Status& status, const fs::path& file) {
    if (!status) {
        report->fail("plot", status);
    } else {
        log::info("wrote ", file.string());
    }
}

/// Camera trajectory: ATE, RPE over 1 s and over 1 frame. Returns the ATE alignment.
std::optional<Eigen::Isometry3d> score_camera(const fs::path& seq, const fs::path& run,
                                              const RunOptions& options, RunReport* report) {
    const fs::path est_file = run / "trajectory.txt", gt_file = seq / "groundtruth.txt";
    if (!file_exists(est_file)) {
        report->skip("camera trajectory: no " + est_file.string());
        return std::nullopt;
    }
    auto gt = eval::load_trajectory(gt_file.string());
    if (!gt) {
        report->fail("camera trajectory", gt.status());
        return std::nullopt;
    }
    auto est = eval::load_trajectory(est_file.string());
    if (!est) {
        report->fail("camera trajectory", est.status());
        return std::nullopt;
    }
    for (const auto* w : {&gt->warnings, &est->warnings}) {
        for (const auto& text : *w) log::warn(text);
    }
    auto ate = eval::compute_ate(gt->poses, est->poses, options.association);
    if (!ate) {
        report->fail("camera ATE", ate.status());
        return std::nullopt;
    }
    std::fputs(eval::format_ate(*ate, "Camera ATE").c_str(), stdout);
    report->doc["camera"]["ate"] = eval::to_json(*ate);
    std::optional<eval::RpeResult> first_rpe;
    for (const auto unit : {eval::DeltaUnit::kSeconds, eval::DeltaUnit::kFrames}) {
        eval::RpeConfig config;
        config.unit = unit;
        config.offset_s = options.association.offset_s;
        const std::string key = std::string("rpe_1") + eval::to_string(unit);
        auto rpe = eval::compute_rpe(gt->poses, est->poses, config);
        if (!rpe) {
            report->fail("camera RPE over 1 " + std::string(eval::to_string(unit)), rpe.status());
            continue;
        }
        std::fputs(eval::format_rpe(*rpe, "Camera RPE").c_str(), stdout);
        report->doc["camera"][key] = eval::to_json(*rpe);
        if (!first_rpe) first_rpe = std::move(*rpe);
    }
    if (options.plots) {
        plot(report,
             eval::plot_ate((run / "eval_ate.png").string(), *ate, gt->poses, est->poses, "camera"),
             run / "eval_ate.png");
        if (first_rpe) {
            plot(report, eval::plot_rpe((run / "eval_rpe.png").string(), *first_rpe, "camera"),
                 run / "eval_rpe.png");
        }
    }
    return ate->gt_T_est;
}

std::vector<fs::path> files_with_extension(const fs::path& dir, const std::string& ext) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (e.path().extension() == ext) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Object maps (RUN_DIR/objects.json): objects associated with instances by mask overlap, each
/// pair scored with both frames aligned (the worlds by the camera ATE alignment).
void score_object_maps(const fs::path& seq, const fs::path& run, const RunOptions& options,
                       const std::optional<Eigen::Isometry3d>& gt_T_est, RunReport* report) {
    eval::ObjectMapsConfig config;
    config.association = options.object_association;
    config.stamps = options.association;
    config.model = options.object_model;
    if (!gt_T_est) {
        log::warn("objects: no camera ATE alignment; world alignment: none (identity)");
    }
    auto result = eval::score_object_maps(seq.string(), run.string(), gt_T_est, config);
    if (!result) return report->fail("objects", result.status());
    for (const std::string& w : result->warnings) log::warn(w);
    for (const std::string& e : result->errors) report->fail(e);
    std::fputs(
        eval::format_object_maps(*result, "Objects (" + (run / "objects.json").string() + ")")
            .c_str(),
        stdout);
    const nlohmann::json keys = eval::to_json(*result);
    for (const auto& [key, value] : keys.items()) report->doc[key] = value;
    if (!options.plots) return;
    for (const eval::ObjectMapScore& o : result->objects) {
        if (!o.trajectory) continue;
        const fs::path png = run / ("eval_object_" + o.instance.name + ".png");
        plot(report,
             eval::plot_object(
                 png.string(), *o.trajectory, o.gt_poses, o.est_poses,
                 o.instance.name + " (estimated " + std::to_string(o.masks.est_id) + ")"),
             png);
    }
}

/// Object trajectories named as the ground truth's (objects/<name>.txt), from runs before
/// objects.json.
void score_objects_by_name(const fs::path& seq, const fs::path& run, const RunOptions& options,
                           RunReport* report) {
    const fs::path est_dir = run / "objects";
    if (!fs::is_directory(est_dir)) {
        report->skip("objects: no " + est_dir.string());
        return;
    }
    json objects = json::object();
    std::vector<std::string> estimated;
    for (const fs::path& est_file : files_with_extension(est_dir, ".txt")) {
        const std::string name = est_file.stem().string();
        estimated.push_back(name);
        const fs::path gt_file = seq / "objects" / (name + ".txt");
        if (!file_exists(gt_file)) {
            report->fail("object " + name,
                         error(StatusCode::kNotFound, "no ground truth " + gt_file.string() +
                                                          " for " + est_file.string()));
            continue;
        }
        auto gt = eval::load_trajectory(gt_file.string());
        auto est = eval::load_trajectory(est_file.string());
        if (!gt || !est) {
            report->fail("object " + name, !gt ? gt.status() : est.status());
            continue;
        }
        eval::RpeConfig rpe;
        rpe.offset_s = options.association.offset_s;
        auto object = eval::compute_object_errors(gt->poses, est->poses, options.association, rpe);
        if (!object) {
            report->fail("object " + name, object.status());
            continue;
        }
        std::fputs(eval::format_object(*object, "Object " + name).c_str(), stdout);
        objects[name] = eval::to_json(*object);
        if (options.plots) {
            const fs::path png = run / ("eval_object_" + name + ".png");
            plot(report, eval::plot_ate(png.string(), object->ate, gt->poses, est->poses, name),
                 png);
        }
    }
    json missed = json::array();
    for (const fs::path& gt_file : files_with_extension(seq / "objects", ".txt")) {
        const std::string name = gt_file.stem().string();
        if (std::find(estimated.begin(), estimated.end(), name) == estimated.end()) {
            missed.push_back(name);
        }
    }
    report->doc["objects"] = objects;
    report->doc["objects_not_estimated"] = missed;
}

void score_map(const fs::path& seq, const fs::path& run, const RunOptions& options,
               const std::optional<Eigen::Isometry3d>& gt_T_est, RunReport* report) {
    const fs::path est_file = run / "map.ply", gt_file = seq / "models" / "static.ply";
    if (!file_exists(est_file)) {
        report->skip("reconstruction: no " + est_file.string());
        return;
    }
    auto gt = io::read_ply(gt_file.string());
    if (!gt) return report->fail("reconstruction", gt.status());
    auto est = io::read_ply(est_file.string());
    if (!est) return report->fail("reconstruction", est.status());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    std::string frame = "as written";
    if (options.align_map && gt_T_est) {
        T = *gt_T_est;
        frame = "moved by the camera ATE alignment";
    } else if (options.align_map) {
        log::warn("reconstruction: no camera ATE alignment; scoring the map as written");
    }
    auto recon = eval::score_reconstruction(
        gt->positions, eval::transform_points(T, est->positions), options.reconstruction);
    if (!recon) return report->fail("reconstruction", recon.status());
    std::fputs(eval::format_reconstruction(*recon, "Reconstruction (map " + frame + ")").c_str(),
               stdout);
    report->doc["reconstruction"] = eval::to_json(*recon);
    report->doc["reconstruction"]["map_frame"] = frame;
    // The ATE alignment fits camera positions only: over a short or straight path its rotation
    // is loosely held (0.6 degrees, 3 cm at 3 m, on 60 frames of static_xyz whose ATE is
    // 0.06 cm), which the map's figures would charge to the map. Also scored after registration.
    auto registered =
        eval::score_registered(gt->positions, est->positions, T, options.reconstruction);
    if (!registered) {
        report->doc["reconstruction"]["registered_skipped"] = registered.status().message();
        return;
    }
    std::fputs(eval::format_reconstruction(
                   registered->score,
                   "Reconstruction after rigid registration onto the model (" +
                       eval::format_registration(registered->registration) + ")")
                   .c_str(),
               stdout);
    report->doc["reconstruction"]["registered"] = eval::to_json(registered->score);
    report->doc["reconstruction"]["registered"]["registration"] =
        eval::to_json(registered->registration);
}

void score_masks(const fs::path& seq, const fs::path& run, const RunOptions& options,
                 RunReport* report) {
    const fs::path pred_dir = run / "masks";
    if (!fs::is_directory(pred_dir)) {
        report->skip("segmentation: no " + pred_dir.string());
        return;
    }
    eval::SegmentationConfig config = options.segmentation;
    Progress progress("frames scored (segmentation)", -1, 200);
    config.progress = [&progress](int done, int total) {
        progress.set_total(total);
        progress.update(done);
    };
    auto seg = eval::score_segmentation_folders(seq.string(), pred_dir.string(), config);
    progress.finish();
    if (!seg) return report->fail("segmentation", seg.status());
    std::fputs(eval::format_segmentation(*seg, "Segmentation").c_str(), stdout);
    report->doc["segmentation"] = eval::to_json(*seg);
}

void score_timing(const fs::path& run, RunReport* report) {
    const auto logs = files_with_extension(run, ".log");
    if (logs.empty()) {
        report->skip("timing: no *.log in " + run.string());
        return;
    }
    std::vector<eval::TimingSample> samples;
    for (const fs::path& file : logs) {
        auto parsed = eval::read_timing_log(file.string());
        if (!parsed) return report->fail("timing", parsed.status());
        for (const auto& e : parsed->errors) log::warn(e);
        samples.insert(samples.end(), parsed->samples.begin(), parsed->samples.end());
    }
    const auto stats = eval::summarize_timing(samples);
    std::fputs(eval::format_timing(stats, "Timing").c_str(), stdout);
    report->doc["timing"] = eval::to_json(stats);
}

}  // namespace

int cmd_run(const std::string& sequence_dir, const std::string& run_dir,
            const RunOptions& options) {
    const fs::path seq(sequence_dir), run(run_dir);
    for (const fs::path& dir : {seq, run}) {
        if (!fs::is_directory(dir)) {
            log::error(dir.string(), ": no such folder");
            return 1;
        }
    }
    RunReport report;
    report.doc["sequence"] = sequence_dir;
    report.doc["run"] = run_dir;
    const auto gt_T_est = score_camera(seq, run, options, &report);
    if (file_exists(run / "objects.json")) {
        score_object_maps(seq, run, options, gt_T_est, &report);
    } else {
        score_objects_by_name(seq, run, options, &report);
    }
    score_map(seq, run, options, gt_T_est, &report);
    score_masks(seq, run, options, &report);
    score_timing(run, &report);
    if (report.errors.empty() && report.doc.size() == 2) {  // only "sequence" and "run"
        log::error(run_dir,
                   ": nothing to score (no trajectory.txt, objects.json, objects/, map.ply, "
                   "masks/ or "
                   "*.log); is it a run folder?");
        return 1;
    }
    report.doc["errors"] = report.errors;
    report.doc["skipped"] = report.skipped;
    const fs::path json_file = run / "eval.json";
    const Status s = eval::write_json(json_file.string(), report.doc);
    if (!s) {
        log::error(s.message());
        return 1;
    }
    log::info("wrote ", json_file.string(), report.errors.empty() ? "" : " (with errors)");
    return report.errors.empty() ? 0 : 1;
}

}  // namespace df::eval_cli
