#include "slam_system/slam_system.hpp"
#include "slam_system/stage_clock.hpp"

#include <algorithm>
#include <chrono>
#include <opencv2/imgproc.hpp>

#include "slam/depth_maps.hpp"
#include "slam/pose.hpp"

namespace df::slam {
std::vector<std::pair<std::string, double>> StageTimes::steps() const {
    return {{"preprocess", preprocess_ms},
            {"tracking", tracking_ms},
            {"fusion", fusion_ms},
            {"stage1", stage1_ms},
            {"motion", motion_ms},
            {"stage2", stage2_ms},
            {"objects_predict", objects_predict_ms},
            {"objects_track", objects_track_ms},
            {"objects_map", objects_map_ms},
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

Result<SlamSystem> SlamSystem::restore(const SystemConfig& config, SystemState state) {
    if (!state.world_T_camera.matrix().allFinite() || !state.last_motion.matrix().allFinite()) {
        return error(StatusCode::kInvalidArgument, "restored pose is not finite");
    }
    auto system = create(config, state.world_T_camera);
    if (!system) return system.status();
    DF_RETURN_IF_ERROR(system->static_.map().restore(std::move(state.surfels),
                                                     state.surfels_rejected_by_capacity));
    system->last_motion_ = orthonormalized(state.last_motion);
    system->trajectory_ = std::move(state.trajectory);
    system->frames_ = state.frames;
    system->lost_frames_ = state.lost_frames;
    system->map_time_ = state.map_time;
    system->started_ = state.started;
    system->lost_ = state.lost;
    system->input_size_ = cv::Size(state.input_width, state.input_height);
    if (state.started) system->static_.mark_model_stale();
    DF_RETURN_IF_ERROR(system->objects_.restore(std::move(state.objects)));
    return system;
}

SystemState SlamSystem::state() const {
    SystemState s;
    s.surfels = static_.map().surfels();
    s.surfels_rejected_by_capacity = static_.map().total_rejected_by_capacity();
    s.world_T_camera = world_T_camera_;
    s.last_motion = last_motion_;
    s.trajectory = trajectory_;
    s.frames = frames_;
    s.lost_frames = lost_frames_;
    s.map_time = map_time_;
    s.started = started_;
    s.lost = lost_;
    s.input_width = input_size_.width;
    s.input_height = input_size_.height;
    s.objects = objects_.state();
    return s;
}

SlamSystem::SlamSystem(const SystemConfig& config, const Eigen::Isometry3d& initial)
    : config_(config),
      static_(0, config.map),
      objects_(config.objects, config.tracking, config.map, config.prediction, config.preprocess),
      world_T_camera_(orthonormalized(initial)) {}

Result<FrameReport> SlamSystem::process(const io::RgbdImage& image,
                                        const dynamics::FrameSegments& segments) {
    const auto start = std::chrono::steady_clock::now();
    const std::string where = "frame " + std::to_string(frames_);
    FrameReport report;
    report.frame_number = frames_;
    report.sensor_ns = image.sensor_ns;
    Input in;
    DF_RETURN_IF_ERROR(prepare(image, segments, where, &in, &report));
    rebuild_if_needed(&report);
    carry_instances(&in, &report);
    // With keep_until_moving the memory holds only proven movers' pixels (what was left out),
    // so it is recalled after the object maps decided which rigid instances stay in.
    const bool recall_first = !config_.objects.keep_until_moving;
    if (recall_first) recall_instances(&in);
    const Eigen::Isometry3d guess = pose_guess();
    DF_RETURN_IF_ERROR(predict_objects(guess, &in, &report).with_context(where));
    if (!recall_first) recall_instances(&in);
    if (!started_) {
        report.first = true;
        report.tracking.state = TrackingState::kOk;
        report.tracking.world_T_camera = world_T_camera_;
        report.stage1 = report.tracking;
        report.invalid = dynamics::combine(in.segments, in.instance_ids, cv::Mat(), cv::Mat(),
                                           config_.dynamics.invalid);
        keep_explained_out_of_fusion(in, &report.invalid);
    } else {
        DF_RETURN_IF_ERROR(track_static(in, guess, &report).with_context(where));
    }
    update_pose(image.sensor_ns, &report);
    remember(in);
    input_size_ = image.depth.size();
    if (report.tracking.state == TrackingState::kOk || config_.system.fuse_when_lost) {
        DF_RETURN_IF_ERROR(map_static(in, &report).with_context(where));
    }
    if (report.tracking.state == TrackingState::kOk) {
        DF_RETURN_IF_ERROR(map_objects(&in, &report).with_context(where));
    }
    ++frames_;
    report.times.total_ms = ms_since(start);
    return report;
}

Status SlamSystem::prepare(const io::RgbdImage& image, const dynamics::FrameSegments& segments,
                           const std::string& where, Input* in, FrameReport* report) const {
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
    const int f = config_.system.processing_downscale;
    if (image.depth.cols % f != 0 || image.depth.rows % f != 0) {
        return error(StatusCode::kInvalidArgument,
                     where + ": image size not divisible by system.processing_downscale");
    }
    const bool use = config_.dynamics.use_segments || config_.dynamics.motion_segmentation;
    if (use) {
        if (Status s = dynamics::check(segments, image.depth.size(), where); !s) {
            report->segments_error = s.message();
        } else {
            in->segments = dynamics::downscale(segments, f);
        }
    }
    in->image = image;
    in->full = image;
    if (f != 1) {
        const cv::Size size(image.depth.cols / f, image.depth.rows / f);
        // Nearest neighbour: depth is never averaged across an edge or with invalid pixels.
        cv::resize(image.depth, in->image.depth, size, 0, 0, cv::INTER_NEAREST);
        cv::resize(image.rgb, in->image.rgb, size, 0, 0, cv::INTER_AREA);
        // Nearest neighbour of an f x f block picks its top-left pixel: centre u' maps to f u'.
        in->image.intrinsics.fx = image.intrinsics.fx / f;
        in->image.intrinsics.fy = image.intrinsics.fy / f;
        in->image.intrinsics.cx = image.intrinsics.cx / f;
        in->image.intrinsics.cy = image.intrinsics.cy / f;
    }
    const auto t = std::chrono::steady_clock::now();
    Result<Frame> frame = preprocess(in->image, config_.preprocess);
    if (!frame) return frame.status().with_context(where);
    in->frame = std::move(frame).value();
    report->times.preprocess_ms = ms_since(t);
    return Status::ok();
}

Eigen::Isometry3d SlamSystem::pose_guess() const {
    if (config_.system.constant_velocity && !lost_ && started_) {
        return orthonormalized(world_T_camera_ * last_motion_);
    }
    return world_T_camera_;
}

Status SlamSystem::predict_objects(const Eigen::Isometry3d& guess, Input* in, FrameReport* report) {
    if (!config_.objects.enabled || !config_.dynamics.use_segments) return Status::ok();
    const auto t = std::chrono::steady_clock::now();
    const cv::Mat background = static_depth();
    auto objects = objects_.predict_and_associate(in->frame, in->segments.objects, guess, map_time_,
                                                  background);
    if (!objects) return objects.status();
    in->objects = std::move(objects).value();
    // Furniture the static map already holds where it stands stays in its tracking: leaving it
    // out would leave a hole that the next frame, whose detector misses it, shows as a mover. It
    // is not fused, so the map keeps the furniture where it was: were it fused, an object that
    // starts to move slowly would be followed by the map and drag the camera with it.
    const objects::ObjectMapsConfig& c = config_.objects;
    if (c.keep_until_moving) {
        keep_unproven_in_static(in);
    } else if (c.static_explained_fraction < 1.f) {
        for (uint16_t id : objects::explained_by_background(
                 in->segments.objects, in->objects.association, in->frame.levels[0].depth_m,
                 background, c.static_explained_fraction, c.association)) {
            const cv::Mat pixels = in->instance_ids == id;
            hold_out_of_fusion(pixels, in);
            in->instance_ids.setTo(0, pixels);
        }
        in->instances = in->instance_ids != 0;
    }
    // What the object maps claim stays out of the static map, as rigid instances: one row per
    // object for the pixels no instance of the frame left out already.
    int next = 1;
    for (const dynamics::InstanceInfo& row : in->segments.objects.instances)
        next = std::max(next, row.id + 1);
    for (const objects::ObjectReport& r : in->objects.reports) {
        if (r.pixels == 0 || next > 65535) continue;
        const cv::Mat claimed =
            (in->objects.object_ids == static_cast<uint16_t>(r.id)) & (in->instance_ids == 0);
        if (c.keep_until_moving && !r.moving) {
            // A candidate's pixels stay in tracking; until it settled, out of fusion.
            if (!r.settled) hold_out_of_fusion(claimed, in);
            continue;
        }
        const int pixels = cv::countNonZero(claimed);
        if (pixels == 0) continue;
        dynamics::InstanceInfo row;
        row.id = static_cast<uint16_t>(next++);
        row.class_id = r.class_id;
        row.score = 1.f;
        row.kind = dynamics::ObjectKind::kRigid;
        row.pixels = pixels;
        in->segments.objects.instances.push_back(row);
        in->instance_ids.setTo(row.id, claimed);
        in->instances.setTo(255, claimed);
    }
    report->times.objects_predict_ms = ms_since(t);
    return Status::ok();
}

void SlamSystem::keep_unproven_in_static(Input* in) const {
    // The rigid instances matched to a proven mover stay left out; every other rigid instance
    // (matched to a map not proven moving, or to none) is kept in the static map's tracking,
    // and in its fusion once its map settled (objects.settle_after_frames): a mover is not built
    // into the static map before its own tracking could show it moving. Persons and instances
    // of unknown kind are not rigid and stay out.
    enum : uint8_t { kKeep = 0, kTrackOnly = 1, kTrackAndFuse = 2 };
    std::vector<uint8_t> mover(65536, 0), settled(65536, 0);
    const objects::Association& a = in->objects.association;
    for (size_t k = 0; k < a.instance_of_view.size() && k < in->objects.reports.size(); ++k) {
        const uint16_t id = a.instance_of_view[k];
        if (id == 0) continue;
        if (in->objects.reports[k].moving) mover[id] = 1;
        if (in->objects.reports[k].settled) settled[id] = 1;
    }
    std::vector<uint8_t> release(65536, kKeep);
    bool any = false;
    for (const dynamics::InstanceInfo& row : in->segments.objects.instances) {
        if (row.kind == dynamics::ObjectKind::kRigid && !mover[row.id]) {
            release[row.id] = settled[row.id] ? kTrackAndFuse : kTrackOnly;
            any = true;
        }
    }
    if (!any) return;
    cv::Mat track_only = cv::Mat::zeros(in->instance_ids.size(), CV_8UC1);
    for (int y = 0; y < in->instance_ids.rows; ++y) {
        uint16_t* l = in->instance_ids.ptr<uint16_t>(y);
        uint8_t* t = track_only.ptr<uint8_t>(y);
        for (int x = 0; x < in->instance_ids.cols; ++x) {
            if (release[l[x]] == kKeep) continue;
            t[x] = release[l[x]] == kTrackOnly ? 255 : 0;
            l[x] = 0;
        }
    }
    hold_out_of_fusion(track_only, in);
    in->instances = in->instance_ids != 0;
}

void SlamSystem::hold_out_of_fusion(const cv::Mat& pixels, Input* in) {
    if (cv::countNonZero(pixels) == 0) return;
    if (in->explained.empty()) in->explained = cv::Mat::zeros(pixels.size(), CV_8UC1);
    in->explained.setTo(255, pixels);
}

void SlamSystem::keep_explained_out_of_fusion(const Input& in, dynamics::InvalidMask* invalid) {
    if (in.explained.empty()) return;
    if (invalid->fusion.empty()) invalid->fusion = cv::Mat::zeros(in.explained.size(), CV_8UC1);
    invalid->fusion.setTo(255, in.explained);
}

cv::Mat SlamSystem::static_depth() const {
    cv::Mat z;
    if (!static_.model().vertex.empty()) cv::extractChannel(static_.model().vertex, z, 2);
    return z;
}

Status SlamSystem::map_objects(Input* in, FrameReport* report) {
    if (!config_.objects.enabled || !config_.dynamics.use_segments) return Status::ok();
    auto t = std::chrono::steady_clock::now();
    if (config_.objects.from_motion && report->motion.moving) {
        // Unknown movers as objects: motion segmentation's regions may create maps of their own.
        objects::add_motion_regions(report->motion.mask, in->objects.object_ids,
                                    config_.objects.min_create_pixels, &in->segments.objects,
                                    &in->objects.association);
    }
    DF_RETURN_IF_ERROR(
        objects_.track(in->frame, in->segments.objects, world_T_camera_, map_time_, &in->objects));
    report->times.objects_track_ms = ms_since(t);
    t = std::chrono::steady_clock::now();
    DF_RETURN_IF_ERROR(objects_.map(in->frame, in->image.rgb, in->full, in->segments.objects,
                                    world_T_camera_, map_time_, frames_, static_depth(),
                                    &in->objects));
    report->times.objects_map_ms = ms_since(t);
    report->objects = in->objects.reports;
    report->object_ids = in->objects.object_ids;
    return Status::ok();
}

Status SlamSystem::track_static(const Input& in, const Eigen::Isometry3d& guess,
                                FrameReport* report) {
    const DynamicsOptions& d = config_.dynamics;
    if (static_.model_stale()) {
        // Restored from a checkpoint: the model is the map seen from the restored pose.
        DF_RETURN_IF_ERROR(predict_model(in.frame, report));
    }
    auto t = std::chrono::steady_clock::now();
    const bool any_instances = cv::countNonZero(in.instances) > 0;
    const cv::Mat stage1_mask = any_instances ? in.instances : cv::Mat();
    Result<TrackingResult> stage1 = static_.track(in.frame, guess, stage1_mask, config_.tracking);
    if (!stage1) return stage1.status();
    report->stage1 = *stage1;
    report->tracking = *stage1;
    report->times.stage1_ms = ms_since(t);

    cv::Mat residual;
    // Stage 1 may fail its checks because of the movers themselves (a person filling half the
    // view): motion segmentation and stage 2 then start from what it converged to, and stage 2's
    // checks decide.
    const Eigen::Isometry3d& stage1_pose = stage1->estimate;
    if (d.motion_segmentation) {
        t = std::chrono::steady_clock::now();
        cv::Mat photometric;
        TrackingConfig residual_config = config_.tracking;
        residual_config.max_depth_m = d.motion.max_depth_m;  // motion looks farther (0: all)
        Result<cv::Mat> r =
            static_.residuals(in.frame, stage1_pose, residual_config,
                              d.motion.min_photometric > 0 ? &photometric : nullptr);
        if (!r) return r.status();
        residual = std::move(r).value();
        dynamics::MotionInput motion;
        motion.residual_m = residual;
        motion.depth_m = in.frame.levels[0].depth_m;
        motion.excluded = stage1_mask;
        motion.geometric = in.segments.geometric;
        motion.geometric_count = in.segments.geometric_count;
        motion.photometric = photometric;
        const io::Intrinsics& k = in.frame.levels[0].intrinsics;
        // The older and the previous frame's projections are made only if the frame gets as
        // far as growing segments (segment_motion calls these then).
        const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy),
                    cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
        if (d.motion.history_frames > 0 &&
            history_.size() == static_cast<size_t>(d.motion.history_frames)) {
            motion.history_source = [&, fx, fy, cx, cy](const cv::Mat& needed) {
                const HistoryFrame& old = history_.front();
                const Eigen::Isometry3d old_T_current = old.world_T_camera.inverse() * stage1_pose;
                return dynamics::history_evidence(in.frame.levels[0].vertex, residual, old.depth_m,
                                                  old.rigid, old_T_current.cast<float>(), fx, fy,
                                                  cx, cy, d.motion, needed);
            };
        }
        // Free space an older frame saw that this one fills: the oldest frame kept (in a
        // run's first frames, fewer back than history_frames).
        if (d.motion.free_space_filled && !history_.empty()) {
            motion.filled_source = [&, fx, fy, cx, cy](const cv::Mat& candidates) {
                const HistoryFrame& old = history_.front();
                const Eigen::Isometry3d old_T_current = old.world_T_camera.inverse() * stage1_pose;
                return dynamics::free_space_filled(
                    in.frame.levels[0].vertex,
                    old.far_depth_m.empty() ? old.depth_m : old.far_depth_m,
                    old_T_current.cast<float>(), fx, fy, cx, cy, d.motion, candidates);
            };
        }
        if (d.carry_forward && !previous_motion_.empty() && !lost_) {
            motion.carried_source = [&, fx, fy, cx, cy](const cv::Mat& needed) {
                const Eigen::Isometry3d previous_T_current =
                    world_T_camera_.inverse() * stage1_pose;
                return dynamics::warp_mask(previous_motion_, in.frame.levels[0].vertex,
                                           previous_T_current.cast<float>(), fx, fy, cx, cy,
                                           needed);
            };
        }
        Result<dynamics::MotionResult> m = dynamics::segment_motion(motion, d.motion);
        if (!m) return m.status();
        report->motion = std::move(m).value();
        report->times.motion_ms = ms_since(t);
    }
    previous_motion_ = report->motion.mask;
    report->invalid =
        dynamics::combine(in.segments, in.instance_ids, report->motion.mask, residual, d.invalid);
    keep_explained_out_of_fusion(in, &report->invalid);
    report->guard = guard_reason(in, report->invalid);
    if (!report->guard.empty()) {
        ++guards_.frames_guarded;
        return track_guarded(in, guess, residual, report);
    }

    const bool stage1_ok = stage1->state == TrackingState::kOk;
    const bool rescuable =
        stage1_ok || static_cast<float>(report->motion.mask_pixels) <=
                         d.max_rescue_fraction * static_cast<float>(report->motion.residual_pixels);
    if (report->motion.moving && rescuable) {
        t = std::chrono::steady_clock::now();
        TrackingConfig refine = config_.tracking;
        refine.iterations = d.refine_iterations;
        // A good stage 1 needs only a few refining iterations; a rejected one is tracked again
        // from the initial guess, in full, so its checks (how far it moved) see the whole step.
        if (!stage1_ok) refine.iterations = config_.tracking.iterations;
        Result<TrackingResult> stage2 = static_.track(in.frame, stage1_ok ? stage1_pose : guess,
                                                      report->invalid.tracking, refine);
        if (!stage2) return stage2.status();
        report->stage2 = *stage2;
        report->stage2_ran = true;
        // A refinement that fails its checks (too little left, say) keeps stage 1's pose.
        if (stage2->state == TrackingState::kOk) report->tracking = *stage2;
        report->times.stage2_ms = ms_since(t);
    }
    report->times.tracking_ms =
        report->times.stage1_ms + report->times.motion_ms + report->times.stage2_ms;
    static_.set_last_tracking(report->tracking);
    return Status::ok();
}

void SlamSystem::update_pose(int64_t sensor_ns, FrameReport* report) {
    const bool ok = report->tracking.state == TrackingState::kOk;
    if (ok) {
        if (!report->first) {
            last_motion_ =
                orthonormalized(world_T_camera_.inverse() * report->tracking.world_T_camera);
        }
        world_T_camera_ = report->tracking.world_T_camera;
        trajectory_.push_back(io::stamped_pose(sensor_ns, world_T_camera_));
        lost_run_ = 0;
    } else {
        ++lost_frames_;
        ++lost_run_;
    }
    lost_ = !ok;
    report->world_T_camera = world_T_camera_;
    started_ = true;
}

Status SlamSystem::map_static(const Input& in, FrameReport* report) {
    // ElasticFusion's order: fusion associates pixels with the surfels the map shows at the new
    // pose (every active surfel), then the map is predicted again, after fusion, as the model
    // the next frame is tracked against (confident surfels only, once there are some). With
    // system.model_from_association the one rendering serves both (MapInstance).
    ++map_time_;
    const auto t = std::chrono::steady_clock::now();
    const cv::Mat& mask = report->invalid.fusion;
    const bool masked = !mask.empty() && cv::countNonZero(mask) > 0;
    const map::PredictionConfig model = model_prediction();
    Result<map::FusionStats> stats = static_.fuse(
        in.frame, in.image.rgb, masked ? mask : cv::Mat(), world_T_camera_, map_time_,
        config_.system.associate_by_prediction, model, true, config_.system.model_from_association);
    if (!stats) return stats.status();
    report->fused = true;
    report->fusion = *stats;
    report->times.fusion_ms = ms_since(t);
    return predict_model(in.frame, report, config_.system.model_from_association);
}

map::PredictionConfig SlamSystem::model_prediction() const {
    map::PredictionConfig prediction = config_.prediction;
    prediction.min_confidence = map_time_ - map_start_time_ <= config_.system.bootstrap_frames
                                    ? 0.f
                                    : config_.system.predict_min_confidence;
    return prediction;
}

Status SlamSystem::predict_model(const Frame& frame, FrameReport* report, bool reuse_association) {
    const auto t = std::chrono::steady_clock::now();
    const map::PredictionConfig prediction = model_prediction();
    bool reused = false;
    if (reuse_association) {
        Result<bool> r = static_.model_from_association(frame, world_T_camera_, prediction);
        if (!r) return r.status();
        reused = *r;
    }
    if (!reused) {
        DF_RETURN_IF_ERROR(static_.predict_model(frame, world_T_camera_, map_time_, prediction));
    }
    report->times.prediction_ms += ms_since(t);
    return Status::ok();
}

Status SlamSystem::write_trajectory(const std::string& file) const {
    return io::write_tum_trajectory(file, trajectory_);
}

Status SlamSystem::write_map(const std::string& file, bool stable_only) const {
    return static_.map().write_ply(file, stable_only);
}

}  // namespace df::slam
