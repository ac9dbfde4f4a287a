#include "slam_system/slam_system.hpp"

#include <chrono>
#include <opencv2/imgproc.hpp>

#include "slam/pose.hpp"

namespace df::slam {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

io::StampedPose stamped(int64_t sensor_ns, const Eigen::Isometry3d& pose) {
    io::StampedPose p;
    p.stamp_s = static_cast<double>(sensor_ns) * 1e-9;
    p.t = pose.translation();
    p.q = Eigen::Quaterniond(pose.linear()).normalized();
    return p;
}

}  // namespace

std::vector<std::pair<std::string, double>> StageTimes::steps() const {
    return {{"preprocess", preprocess_ms},
            {"tracking", tracking_ms},
            {"fusion", fusion_ms},
            {"prediction", prediction_ms},
            {"total", total_ms}};
}

Result<SlamSystem> SlamSystem::create(const SystemConfig& config,
                                      const Eigen::Isometry3d& initial_world_T_camera) {
    if (std::string e = validate(config); !e.empty()) {
        return error(StatusCode::kInvalidArgument, "SLAM configuration: " + e);
    }
    return SlamSystem(config, initial_world_T_camera);
}

SlamSystem::SlamSystem(const SystemConfig& config, const Eigen::Isometry3d& initial)
    : config_(config), map_(config.map), world_T_camera_(orthonormalized(initial)) {}

void SlamSystem::downscale(const io::RgbdImage& in, const cv::Mat& mask_in, io::RgbdImage* out,
                           cv::Mat* mask_out) const {
    const int f = config_.system.processing_downscale;
    *out = in;
    *mask_out = mask_in;
    if (f == 1) return;
    const cv::Size size(in.depth.cols / f, in.depth.rows / f);
    // Nearest neighbour: depth is never averaged across an edge or with invalid pixels.
    cv::resize(in.depth, out->depth, size, 0, 0, cv::INTER_NEAREST);
    cv::resize(in.rgb, out->rgb, size, 0, 0, cv::INTER_AREA);
    if (!mask_in.empty()) cv::resize(mask_in, *mask_out, size, 0, 0, cv::INTER_NEAREST);
    // Nearest neighbour of an f x f block picks its top-left pixel: pixel centre u' maps to u = f u'.
    out->intrinsics.fx = in.intrinsics.fx / f;
    out->intrinsics.fy = in.intrinsics.fy / f;
    out->intrinsics.cx = in.intrinsics.cx / f;
    out->intrinsics.cy = in.intrinsics.cy / f;
}

Result<FrameReport> SlamSystem::process(const io::RgbdImage& image, const cv::Mat& mask) {
    const auto start = std::chrono::steady_clock::now();
    const std::string where = "frame " + std::to_string(frames_);
    if (image.depth.empty() || image.rgb.empty()) {
        return error(StatusCode::kInvalidArgument, where + ": empty depth or colour image");
    }
    if (started_ && image.depth.size() != input_size_) {
        return error(StatusCode::kInvalidArgument,
                     where + ": image size " + std::to_string(image.depth.cols) + "x" +
                         std::to_string(image.depth.rows) + " differs from the first frame's " +
                         std::to_string(input_size_.width) + "x" +
                         std::to_string(input_size_.height));
    }
    if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != image.depth.size())) {
        return error(StatusCode::kInvalidArgument,
                     where + ": mask must be CV_8UC1 of the image's size, got " +
                         cv::typeToString(mask.type()) + " " + std::to_string(mask.cols) + "x" +
                         std::to_string(mask.rows));
    }
    if (image.depth.cols % config_.system.processing_downscale != 0 ||
        image.depth.rows % config_.system.processing_downscale != 0) {
        return error(StatusCode::kInvalidArgument,
                     where + ": image size not divisible by system.processing_downscale");
    }
    io::RgbdImage work;
    cv::Mat work_mask;
    downscale(image, mask, &work, &work_mask);

    FrameReport report;
    report.frame_number = frames_;
    report.sensor_ns = image.sensor_ns;
    auto t = std::chrono::steady_clock::now();
    Result<Frame> frame = preprocess(work, config_.preprocess);
    if (!frame) return frame.status().with_context(where);
    report.times.preprocess_ms = ms_since(t);

    if (!started_) {
        report.first = true;
        report.tracking.state = TrackingState::kOk;
        report.tracking.world_T_camera = world_T_camera_;
    } else {
        t = std::chrono::steady_clock::now();
        Eigen::Isometry3d guess = world_T_camera_;
        if (config_.system.constant_velocity && !lost_) {
            guess = orthonormalized(world_T_camera_ * last_motion_);
        }
        Result<TrackingResult> tracked =
            track(*frame, model_, world_T_model_, guess, work_mask, config_.tracking);
        if (!tracked) return tracked.status().with_context(where);
        report.tracking = *tracked;
        report.times.tracking_ms = ms_since(t);
    }
    const bool ok = report.tracking.state == TrackingState::kOk;
    if (ok) {
        if (!report.first) {
            last_motion_ =
                orthonormalized(world_T_camera_.inverse() * report.tracking.world_T_camera);
        }
        world_T_camera_ = report.tracking.world_T_camera;
        trajectory_.push_back(stamped(image.sensor_ns, world_T_camera_));
    } else {
        ++lost_frames_;
    }
    lost_ = !ok;
    report.world_T_camera = world_T_camera_;
    started_ = true;
    input_size_ = image.depth.size();

    if (ok || config_.system.fuse_when_lost) {
        // ElasticFusion's order: fusion associates pixels with the surfels the map shows at the
        // new pose (every active surfel), then the map is predicted again, after fusion, as the
        // model the next frame is tracked against (confident surfels only, once there are some).
        ++map_time_;
        cv::Mat association;
        if (config_.system.associate_by_prediction && map_.size() > 0) {
            DF_RETURN_IF_ERROR(predict(*frame, 0.f, &association_, &report).with_context(where));
            association = association_.index;
        }
        DF_RETURN_IF_ERROR(fuse(*frame, work, work_mask, association, &report).with_context(where));
        const float min_confidence = map_time_ <= config_.system.bootstrap_frames
                                         ? 0.f
                                         : config_.system.predict_min_confidence;
        map::ModelPrediction tracking_model;
        DF_RETURN_IF_ERROR(
            predict(*frame, min_confidence, &tracking_model, &report).with_context(where));
        model_.vertex = tracking_model.vertex;
        model_.normal = tracking_model.normal;
        model_.colour = tracking_model.colour;
        world_T_model_ = world_T_camera_;
    }
    ++frames_;
    report.times.total_ms = ms_since(start);
    return report;
}

Status SlamSystem::fuse(const Frame& frame, const io::RgbdImage& image, const cv::Mat& mask,
                        const cv::Mat& association, FrameReport* report) {
    const auto t = std::chrono::steady_clock::now();
    const FrameLevel& level = frame.levels[0];
    Result<map::FusionStats> stats =
        map_.fuse(level.vertex, level.normal, image.rgb, mask, association,
                  world_T_camera_.cast<float>(), level.intrinsics, map_time_);
    if (!stats) return stats.status();
    report->fused = true;
    report->fusion = *stats;
    report->times.fusion_ms = ms_since(t);
    return Status::ok();
}

Status SlamSystem::predict(const Frame& frame, float min_confidence, map::ModelPrediction* out,
                           FrameReport* report) {
    const auto t = std::chrono::steady_clock::now();
    const FrameLevel& level = frame.levels[0];
    map::PredictionConfig prediction = config_.prediction;
    prediction.min_confidence = min_confidence;
    DF_RETURN_IF_ERROR(map_.predict_into(world_T_camera_.cast<float>(), level.intrinsics,
                                         level.width(), level.height(), map_time_, prediction,
                                         *out));
    report->times.prediction_ms += ms_since(t);
    return Status::ok();
}

Status SlamSystem::write_trajectory(const std::string& file) const {
    return io::write_tum_trajectory(file, trajectory_);
}

Status SlamSystem::write_map(const std::string& file, bool stable_only) const {
    return map_.write_ply(file, stable_only);
}

}  // namespace df::slam
