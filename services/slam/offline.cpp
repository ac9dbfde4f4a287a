#include "offline.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "capture.pb.h"
#include "core/log.hpp"
#include "eval/trajectory_metrics.hpp"
#include "run_outputs.hpp"
#include "service/service.hpp"
#include "slam_params.hpp"
#include "slam_system/parameters.hpp"
#include "source.hpp"

namespace df::slam_service {
namespace {

/// Reads "<folder>/intrinsics.txt" as df_make_sequence writes it ("fx fy cx cy width height
/// depth_units_per_m", '#' comments). False when there is no such file.
Result<bool> read_sequence_intrinsics(const std::string& folder, config::CaptureConfig* c) {
    const std::string file = folder + "/intrinsics.txt";
    std::ifstream in(file);
    if (!in) return false;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        double fx, fy, cx, cy, units;
        int width, height;
        if (!(s >> fx >> fy >> cx >> cy >> width >> height >> units) || fx <= 0 || fy <= 0 ||
            units <= 0) {
            return error(StatusCode::kInvalidArgument,
                         file + ":" + std::to_string(number) +
                             ": expected 'fx fy cx cy width height depth_units_per_m'");
        }
        c->set_fx(fx);
        c->set_fy(fy);
        c->set_cx(cx);
        c->set_cy(cy);
        c->set_depth_units_per_m(units);
        return true;
    }
    return error(StatusCode::kInvalidArgument, file + ": no intrinsics line");
}

Status input_config(const OfflineOptions& o, config::CaptureConfig* c) {
    c->set_folder(o.folder);
    if (o.preset.empty()) {
        Result<bool> found = read_sequence_intrinsics(o.folder, c);
        if (!found) return found.status();
        if (*found) log::info("intrinsics and depth scale from ", o.folder, "/intrinsics.txt");
        return Status::ok();
    }
    c->set_intrinsics_preset(o.preset);
    if (o.preset == "7scenes") {
        c->set_depth_units_per_m(1000);
        c->set_depth_invalid_value(65535);
    }
    return Status::ok();
}

/// The mask of the frame stamped `sensor_ns`, from options.masks (see OfflineOptions).
Result<cv::Mat> read_mask(const OfflineOptions& o, const io::RgbdImage& image) {
    char name[64];
    std::snprintf(name, sizeof name, "%.6f.png", static_cast<double>(image.sensor_ns) * 1e-9);
    const std::string file = o.masks + "/" + name;
    if (!std::filesystem::exists(file)) {
        return error(StatusCode::kNotFound, "no mask " + file + " for this frame");
    }
    const cv::Mat raw = cv::imread(file, cv::IMREAD_UNCHANGED);
    if (raw.empty() || raw.channels() != 1) {
        return error(StatusCode::kInvalidArgument,
                     "mask " + file + " is not a readable single-channel PNG");
    }
    if (raw.size() != image.depth.size()) {
        return error(StatusCode::kInvalidArgument,
                     "mask " + file + " is " + std::to_string(raw.cols) + "x" +
                         std::to_string(raw.rows) + ", the frame " +
                         std::to_string(image.depth.cols) + "x" + std::to_string(image.depth.rows));
    }
    cv::Mat mask = raw != 0;
    if (o.mask_dilate_px > 0) {
        const int k = 2 * o.mask_dilate_px + 1;
        cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    }
    return mask;
}

void print_ate(const std::string& gt_file, const std::string& est_file) {
    auto gt = eval::load_trajectory(gt_file);
    auto est = eval::load_trajectory(est_file);
    if (!gt || !est) {
        log::warn("no ATE: ", (!gt ? gt.status() : est.status()).message());
        return;
    }
    auto ate = eval::compute_ate(gt->poses, est->poses);
    if (!ate) {
        log::warn("no ATE: ", ate.status().message());
        return;
    }
    std::printf("ATE RMSE %.2f cm (median %.2f cm, max %.2f cm) over %zu poses, against %s\n",
                ate->translation_m.rmse * 100, ate->translation_m.median * 100,
                ate->translation_m.max * 100, ate->pairs.size(), gt_file.c_str());
}

}  // namespace

int run_offline(const OfflineOptions& options, const config::SlamServiceConfig& config) {
    config::CaptureConfig input;
    if (Status s = input_config(options, &input); !s) {
        log::error(s.message());
        return 1;
    }
    auto source = capture::open_source(input);
    if (!source) {
        log::error("cannot open the input: ", source.status().message());
        return 1;
    }
    log::info("input: ", (*source)->describe());
    if (!options.masks.empty()) {
        if (!std::filesystem::is_directory(options.masks)) {
            log::error("--masks ", options.masks, " is not a folder");
            return 1;
        }
        log::info("masks: ", options.masks, " (non-zero pixels left out, grown by ",
                  options.mask_dilate_px, " px)");
    }
    slam::SystemConfig system_config;
    if (Status s = apply(config.slam(), &system_config); !s) {
        log::error(s.message());
        return 1;
    }
    log::info("SLAM parameters:\n", slam::describe(system_config));
    auto system = slam::SlamSystem::create(system_config);
    if (!system) {
        log::error(system.status().message());
        return 1;
    }
    auto outputs = RunOutputs::open(options.out_dir);
    if (!outputs) {
        log::error(outputs.status().message());
        return 1;
    }
    const auto start = std::chrono::steady_clock::now();
    uint64_t bad_frames = 0, seq = 0;
    bool was_lost = false;
    while (!service::stop_requested()) {
        if (options.max_frames > 0 && seq >= options.max_frames) break;
        io::FrameRead read = (*source)->next();
        if (read.kind == io::FrameRead::Kind::kEnd) break;
        if (read.kind == io::FrameRead::Kind::kBadFrame) {
            log::error("seq=", seq, " bad frame skipped: ", read.error);
            ++bad_frames;
            ++seq;
            continue;
        }
        cv::Mat mask;
        if (!options.masks.empty()) {
            Result<cv::Mat> m = read_mask(options, read.image);
            if (!m) {
                log::error("seq=", seq, " frame skipped: ", m.status().message());
                ++bad_frames;
                ++seq;
                continue;
            }
            mask = std::move(m).value();
        }
        auto report = system->process(read.image, mask);
        if (!report) {
            log::error("seq=", seq, " frame not processed: ", report.status().message());
            ++bad_frames;
            ++seq;
            continue;
        }
        outputs->add(seq, *report);
        const bool lost = report->tracking.state == slam::TrackingState::kLost;
        if (lost && !was_lost) {
            log::warn("seq=", seq, " tracking lost: ", report->tracking.reason);
        } else if (!lost && was_lost) {
            log::info("seq=", seq, " tracking recovered");
        }
        was_lost = lost;
        const uint32_t every = config.output().log_every();
        if (every > 0 && seq % every == 0) {
            log::info("seq=", seq, " ", slam::to_string(report->tracking.state),
                      " inliers=", report->tracking.inlier_ratio,
                      " icp_rmse_mm=", report->tracking.icp_rmse_m * 1000,
                      " surfels=", report->fusion.total, " fused=", report->fusion.fused,
                      " created=", report->fusion.created,
                      " removed=", report->fusion.removed + report->fusion.removed_free_space,
                      " total_ms=", report->times.total_ms);
        }
        ++seq;
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Status written = outputs->finish(*system, config.output().stable_only(), wall_s);
    std::printf(
        "processed %llu frames (%llu lost, %llu bad) in %.1f s = %.1f frames/s; map %zu "
        "surfels\n",
        static_cast<unsigned long long>(system->frames()),
        static_cast<unsigned long long>(system->lost_frames()),
        static_cast<unsigned long long>(bad_frames), wall_s,
        wall_s > 0 ? static_cast<double>(system->frames()) / wall_s : 0.0,
        system->static_map().size());
    std::printf("trajectory %s\nmap %s\ntimings %s/timings.log\nsummary %s\n",
                outputs->trajectory_file().c_str(), outputs->map_file().c_str(),
                outputs->dir().c_str(), outputs->summary_file().c_str());
    if (!written) {
        log::error(written.message());
        return 1;
    }
    std::string gt = options.groundtruth;
    if (gt.empty() && std::filesystem::exists(options.folder + "/groundtruth.txt"))
        gt = options.folder + "/groundtruth.txt";
    if (!gt.empty()) print_ate(gt, outputs->trajectory_file());
    return system->frames() > 0 ? 0 : 1;
}

}  // namespace df::slam_service
