#include "offline.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "boxes/box_source.hpp"
#include "capture.pb.h"
#include "config/apply_params.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "foxglove_output.hpp"
#include "detect/detector.hpp"
#include "eval/segmentation.hpp"
#include "eval/trajectory_metrics.hpp"
#include "io/tum/intrinsics_file.hpp"
#include "io/tum/stamp.hpp"
#include "mask_outputs.hpp"
#include "objects/object_io.hpp"
#include "run_outputs.hpp"
#include "seg/frame_segmenter.hpp"
#include "service/service.hpp"
#include "slam_system/parameters.hpp"
#include "slam_system/slam_params.hpp"
#include "source.hpp"

namespace df::slam_service {
namespace {

/// Takes "<folder>/intrinsics.txt" (io::read_intrinsics_file, every value checked) into the
/// capture config: intrinsics, image size and depth scale. False when there is no such file.
Result<bool> read_sequence_intrinsics(const std::string& folder, config::CaptureConfig* c) {
    auto file = io::read_intrinsics_file(folder + "/intrinsics.txt");
    if (!file && file.status().code() == StatusCode::kNotFound) return false;
    if (!file) return file.status();
    c->set_fx(file->intrinsics.fx);
    c->set_fy(file->intrinsics.fy);
    c->set_cx(file->intrinsics.cx);
    c->set_cy(file->intrinsics.cy);
    c->set_width(static_cast<uint32_t>(file->width));
    c->set_height(static_cast<uint32_t>(file->height));
    c->set_depth_units_per_m(file->depth_units_per_m);
    return true;
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

/// The masks of the frame stamped `sensor_ns`, from options.masks (see OfflineOptions): a
/// 16-bit instance image (or any single-channel image, non-zero = left out), grown by
/// options.mask_dilate_px. Each id is an instance of the class and kind `table` gives it (a
/// generated sequence's instances.json); ids it lacks, or all with no table, of unknown kind.
Result<dynamics::FrameSegments> read_masks(const OfflineOptions& o, const io::RgbdImage& image,
                                           const std::vector<eval::GtInstance>& table) {
    const std::string file = o.masks + "/" + io::stamp_text(image.sensor_ns) + ".png";
    if (!std::filesystem::exists(file)) {
        return error(StatusCode::kNotFound, "no mask " + file + " for this frame");
    }
    cv::Mat raw = cv::imread(file, cv::IMREAD_UNCHANGED);
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
    if (raw.type() != CV_16UC1) raw = raw != 0;
    if (o.mask_dilate_px > 0) {
        const int k = 2 * o.mask_dilate_px + 1;
        cv::dilate(raw, raw, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    }
    dynamics::FrameSegments segments;
    segments.objects = dynamics::from_labels(raw, dynamics::ObjectKind::kUnknown);
    for (dynamics::InstanceInfo& row : segments.objects.instances) {
        for (const eval::GtInstance& gt : table) {
            if (gt.id != row.id) continue;
            row.class_id = gt.class_id;
            row.score = 1.f;
            row.kind = gt.kind == eval::InstanceKind::kRigid      ? dynamics::ObjectKind::kRigid
                       : gt.kind == eval::InstanceKind::kNonRigid ? dynamics::ObjectKind::kNonRigid
                                                                  : dynamics::ObjectKind::kUnknown;
        }
    }
    return segments;
}

/// The instances.json beside a masks folder (SEQ/instances -> SEQ/instances.json), if any:
/// then ground-truth masks carry their classes and kinds (rigid objects get object maps).
Result<std::vector<eval::GtInstance>> mask_table(const std::string& masks) {
    std::filesystem::path folder(masks);
    if (!folder.has_filename()) folder = folder.parent_path();
    const std::filesystem::path file = folder.parent_path() / "instances.json";
    if (!std::filesystem::exists(file)) return std::vector<eval::GtInstance>{};
    return eval::read_instances_json(file.string());
}

/// Where a frame's segments come from: ground-truth masks, or geometric segmentation and (on
/// its own thread) detection fused as df_geoseg and df_fusion do.
class Segmenter {
  public:
    static Result<Segmenter> open(const OfflineOptions& o, const config::SlamServiceConfig& c) {
        Segmenter s;
        s.options_ = o;
        if (!o.masks.empty()) {
            auto table = mask_table(o.masks);
            if (!table) return table.status().with_context("--masks");
            s.mask_table_ = std::move(table).value();
            if (!s.mask_table_.empty())
                log::info("masks: classes and kinds of ", s.mask_table_.size(),
                          " instances from the instances.json beside them");
        }
        DF_RETURN_IF_ERROR(
            config::apply_params(c.geoseg(), &s.config_.geometric).with_context("geoseg"));
        DF_RETURN_IF_ERROR(
            config::apply_params(c.instances(), &s.config_.instances).with_context("instances"));
        DF_RETURN_IF_ERROR(config::apply_params(c.classes(), &s.classes_).with_context("classes"));
        DF_RETURN_IF_ERROR(detect::check_class_names(s.classes_).with_context("classes"));
        if (std::string e = seg::validate(s.config_.geometric); !e.empty())
            return error(StatusCode::kInvalidArgument, "geoseg." + e);
        if (!o.masks.empty() || o.dynamics == "off" || o.detector == "none") return s;
        config::DetectorServiceConfig d = c.detector();
        if (o.detector == "simulated") {
            d.set_model("simulated");
            d.set_sim_sequence(o.folder);
        }
        auto source = boxes::open_source(d);
        if (!source) return source.status().with_context("detector");
        s.boxes_ = std::move(source).value();
        log::info("detector: ", s.boxes_->describe(), " (own thread)");
        return s;
    }

    /// The segments of `image` (frame `seq`); an error names the frame's file or stage.
    Result<dynamics::FrameSegments> segment(const io::RgbdImage& image, uint64_t seq) {
        if (!options_.masks.empty()) return read_masks(options_, image, mask_table_);
        if (options_.dynamics == "off") return dynamics::FrameSegments{};
        std::future<Result<std::vector<detect::Detection>>> boxes;
        const bool detect = boxes_ && seq % static_cast<uint64_t>(options_.detect_every) == 0;
        if (detect) {
            boxes = std::async(std::launch::async,
                               [this, &image, seq] { return boxes_->detect(image, seq); });
        }
        Result<seg::GeometricSegmentation> geometric = seg::segment_depth(image, config_);
        std::vector<detect::Detection> found;
        int age = 0;
        if (detect) {
            Result<std::vector<detect::Detection>> b = boxes.get();
            if (!b) return b.status().with_context("detector");
            found = std::move(b).value();
            last_boxes_ = found;
            last_detected_ = seq;
        } else if (boxes_) {
            // Not this frame's: the last detection's boxes, as the fusion service reuses them.
            found = last_boxes_;
            age = last_detected_ ? static_cast<int>(seq - *last_detected_) : -1;
        }
        if (!geometric) return geometric.status().with_context("geometric segmentation");
        const auto kind_of = [this](const detect::Detection& d) {
            return detect::class_kind(classes_, d.class_name);
        };
        Result<dynamics::FrameSegments> fused =
            seg::fuse_segments(*geometric, found, kind_of, config_.instances);
        if (fused) fused->detections_age = age;
        return fused;
    }

  private:
    OfflineOptions options_;
    std::vector<eval::GtInstance> mask_table_;  ///< with --masks: instances.json, if any
    seg::FrameSegmenterConfig config_;
    params::fusion::ClassParams classes_;  ///< which classes are rigid / non-rigid
    std::unique_ptr<boxes::BoxSource> boxes_;
    std::vector<detect::Detection> last_boxes_;  ///< of the last frame detected
    std::optional<uint64_t> last_detected_;
};

/// "3 car 812px T, 5 chair 0px -" per live object of the frame (T: tracked; + created).
std::string objects_text(const slam::FrameReport& report) {
    std::string text;
    for (const objects::ObjectReport& r : report.objects) {
        text += (text.empty() ? "" : ",") + std::to_string(r.id) + ":" + class_name(r.class_id) +
                ":" + std::to_string(r.pixels) + "px" + (r.created ? "+" : "") +
                (r.tracked ? "T" : "") + (r.state == objects::ObjectState::kRetired ? "R" : "") +
                (!r.tracked && !r.tracking.reason.empty() ? "(" + r.tracking.reason + ")" : "");
    }
    return text.empty() ? "none" : text;
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
    std::error_code ec;
    if (!options.groundtruth.empty() &&
        !std::filesystem::is_regular_file(options.groundtruth, ec)) {
        log::error("--groundtruth '", options.groundtruth, "' is not a readable file");
        return 1;
    }
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
    if (Status s = slam::apply(config.slam(), &system_config); !s) {
        log::error(s.message());
        return 1;
    }
    if (options.preset == "7scenes" && !config.slam().motion().has_min_photometric()) {
        // 7-Scenes' colour is not registered to its depth: every edge's intensity then differs
        // from the model's by tens of levels, which is no evidence of motion.
        system_config.dynamics.motion.min_photometric = 0.f;
        log::info(
            "7scenes: colour is not registered to depth, so intensity changes are no "
            "motion evidence (slam.motion.min_photometric 0; set it to override)");
    }
    if (options.dynamics == "off") {
        system_config.dynamics.use_segments = false;
        system_config.dynamics.motion_segmentation = false;
        log::info("dynamics off: the static core alone, every pixel tracked and fused");
    } else if (!options.masks.empty()) {
        system_config.dynamics.motion_segmentation = false;
        log::info("ground-truth masks: motion segmentation off");
    }
    auto segmenter = Segmenter::open(options, config);
    if (!segmenter) {
        log::error(segmenter.status().message());
        return 1;
    }
    std::optional<FoxgloveOutput> views;
    if (!options.foxglove.empty()) {
        auto v = FoxgloveOutput::open(options.foxglove, config.map_cloud_every_frames());
        if (!v) {
            log::error("--foxglove: ", v.status().message());
            return 1;
        }
        views.emplace(std::move(*v));
    }
    std::optional<MaskOutputs> masks;
    if (options.write_masks && options.dynamics == "on") {
        auto m = MaskOutputs::open(options.out_dir, options.overlay);
        if (!m) {
            log::error(m.status().message());
            return 1;
        }
        masks.emplace(std::move(*m));
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
    int64_t total = (*source)->size();
    if (options.max_frames > 0 && (total < 0 || total > static_cast<int64_t>(options.max_frames)))
        total = static_cast<int64_t>(options.max_frames);
    Progress progress("frames", total, 100);
    uint64_t bad_frames = 0, seq = 0;
    bool was_lost = false;
    while (!service::stop_requested()) {
        if (options.max_frames > 0 && seq >= options.max_frames) break;
        progress.update(static_cast<int64_t>(seq));
        io::FrameRead read = (*source)->next();
        if (read.kind == io::FrameRead::Kind::kEnd) break;
        if (read.kind == io::FrameRead::Kind::kBadFrame) {
            log::error("seq=", seq, " bad frame skipped: ", read.error);
            ++bad_frames;
            ++seq;
            continue;
        }
        Result<dynamics::FrameSegments> segments = segmenter->segment(read.image, seq);
        if (!segments && !options.masks.empty()) {
            log::error("seq=", seq, " frame skipped: ", segments.status().message());
            ++bad_frames;
            ++seq;
            continue;
        }
        if (!segments) {
            // Segmentation or detection failed for this frame: tracked with motion
            // segmentation alone.
            log::warn("seq=", seq, " no segments (", segments.status().message(),
                      "): motion segmentation alone");
            segments = dynamics::FrameSegments{};
        }
        auto report = system->process(read.image, *segments);
        if (!report) {
            log::error("seq=", seq, " frame not processed: ", report.status().message());
            ++bad_frames;
            ++seq;
            continue;
        }
        outputs->add(seq, *report);
        if (!report->segments_error.empty())
            log::warn("seq=", seq, " segments not used: ", report->segments_error);
        if (views) {
            if (Status w = views->write(seq, read.image, *segments, *report, *system); !w) {
                log::error("seq=", seq, " --foxglove: ", w.message(), "; no more views written");
                views.reset();
            }
        }
        if (masks) {
            if (Status w = masks->write(read.image, *segments, *report,
                                        system_config.system.processing_downscale);
                !w) {
                log::error("seq=", seq, " ", w.message());
            }
        }
        const bool lost = report->tracking.state == slam::TrackingState::kLost;
        if (lost && !was_lost) {
            log::warn("seq=", seq, " tracking lost: ", report->tracking.reason);
        } else if (!lost && was_lost) {
            log::info("seq=", seq, " tracking recovered");
        }
        was_lost = lost;
        const uint32_t every = config.output().log_every();
        if (every > 0 && seq % every == 0) {
            log::info(
                "seq=", seq, " ", slam::to_string(report->tracking.state),
                " inliers=", report->tracking.inlier_ratio,
                " icp_rmse_mm=", report->tracking.icp_rmse_m * 1000,
                " surfels=", report->fusion.total, " fused=", report->fusion.fused,
                " created=", report->fusion.created,
                " removed=", report->fusion.removed + report->fusion.removed_free_space,
                " instances=", report->instances.instances.size(),
                " detections_age=", report->detections_age, " carried=", report->carried,
                " left_out_px=",
                cv::countNonZero(report->invalid.tracking.empty() ? cv::Mat::zeros(1, 1, CV_8UC1)
                                                                  : report->invalid.tracking),
                " motion_px=", report->motion.mask_pixels, " (2-means ",
                report->motion.clusters.low * 1000, "/", report->motion.clusters.high * 1000,
                " mm, ", report->motion.dynamic_pixels, " px above, ", report->motion.segments,
                " segments, ", report->motion.still_segments, " still, photometric > ",
                report->motion.photometric_threshold, ")",
                " stage2=", report->stage2_ran ? slam::to_string(report->stage2.state) : "no",
                " objects=", objects_text(*report), " total_ms=", report->times.total_ms);
        }
        ++seq;
    }
    progress.update(static_cast<int64_t>(seq));
    progress.finish();
    if (views) {
        if (Status c = views->close(); !c) log::error("--foxglove: ", c.message());
        else log::info("Foxglove views of the run in ", options.foxglove);
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
    const std::string objects = objects::describe_objects(system->object_maps(), class_name);
    if (!objects.empty()) {
        std::printf("%zu object map(s), in %s/objects.json:\n%s",
                    system->object_maps().objects().size(), outputs->dir().c_str(),
                    objects.c_str());
    }
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
