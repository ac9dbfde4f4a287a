// SlamSystem's steps on what a frame carries over to the next: the instances carried forward
// over frames without their own detections, the memory of rigid instances, and the motion
// history (the rest of the loop is in slam_system.cpp).
#include <opencv2/core.hpp>

#include "slam/depth_maps.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam {

void SlamSystem::carry_instances(Input* in, FrameReport* report) const {
    const DynamicsOptions& d = config_.dynamics;
    report->detections_age = in->segments.detections_age;
    if (d.use_segments && in->segments.detections_age != 0 && started_ && !lost_) {
        const io::Intrinsics& k = in->frame.levels[0].intrinsics;
        dynamics::LabelImage carried = propagation_.carry(
            in->frame.levels[0].depth_m, in->segments.geometric, in->segments.geometric_count,
            last_motion_.inverse().cast<float>(),
            {static_cast<float>(k.fx), static_cast<float>(k.fy), static_cast<float>(k.cx),
             static_cast<float>(k.cy)},
            d.propagation);
        if (!carried.empty()) {
            report->carried = static_cast<int>(carried.instances.size());
            in->segments.objects = std::move(carried);
        }
    }
    report->instances = in->segments.objects;
    const cv::Size size = in->image.depth.size();
    in->instance_ids = d.use_segments
                           ? dynamics::instance_labels(in->segments, in->frame.levels[0].depth_m,
                                                       size, d.invalid)
                           : cv::Mat::zeros(size, CV_16UC1);
    in->instances = in->instance_ids != 0;
    in->detected_rigid = dynamics::mask_of({in->instance_ids, in->segments.objects.instances},
                                           {dynamics::ObjectKind::kRigid}, size);
}

void SlamSystem::recall_instances(Input* in) {
    const DynamicsOptions& d = config_.dynamics;
    if (!d.use_segments || !d.invalid.rigid || d.memory.frames <= 0) return;
    const cv::Size size = in->instance_ids.size();
    in->rigid = dynamics::mask_of({in->instance_ids, in->segments.objects.instances},
                                  {dynamics::ObjectKind::kRigid}, size);
    if (!started_ || lost_) return;
    const Eigen::Isometry3d previous_T_current =
        config_.system.constant_velocity ? last_motion_ : Eigen::Isometry3d::Identity();
    const FrameLevel& level = in->frame.levels[0];
    const io::Intrinsics& k = level.intrinsics;
    cv::Mat recalled = memory_.recall(level.vertex, previous_T_current.cast<float>(),
                                      static_cast<float>(k.fx), static_cast<float>(k.fy),
                                      static_cast<float>(k.cx), static_cast<float>(k.cy), d.memory);
    recalled.setTo(0, in->instances);
    const int pixels = cv::countNonZero(recalled);
    int id = 1;
    for (const dynamics::InstanceInfo& row : in->segments.objects.instances)
        id = std::max(id, row.id + 1);
    if (pixels == 0 || id > 65535) return;
    dynamics::InstanceInfo row;
    row.id = static_cast<uint16_t>(id);
    row.kind = dynamics::ObjectKind::kRigid;
    row.pixels = pixels;
    in->segments.objects.instances.push_back(row);
    in->instance_ids.setTo(row.id, recalled);
    in->instances.setTo(255, recalled);
}

void SlamSystem::remember(const Input& in) {
    const int frames = config_.dynamics.motion.history_frames;
    if (lost_ || frames <= 0) {
        history_.clear();
    } else {
        const float far = config_.dynamics.motion.seen_through_max_depth_m;
        cv::Mat far_depth;
        if (config_.dynamics.motion.free_space_filled && far > config_.preprocess.max_depth_m &&
            !in.image.depth.empty())
            far_depth = slam::depth_to_metres(in.image.depth, in.image.depth_units_per_m,
                                              config_.preprocess.min_depth_m, far);
        // Rigid: what is left out as rigid now (object maps' claims included) and what the
        // frame came with as rigid instances, kept in the static map or not
        // (keep_until_moving): a candidate seen here was seen as an object, not through.
        cv::Mat rigid = dynamics::mask_of({in.instance_ids, in.segments.objects.instances},
                                          {dynamics::ObjectKind::kRigid}, in.instance_ids.size());
        if (in.detected_rigid.size() == rigid.size()) rigid |= in.detected_rigid;
        history_.push_back({in.frame.levels[0].depth_m, far_depth, rigid, world_T_camera_,
                            in.image.sensor_ns, frames_});
        while (history_.size() > static_cast<size_t>(frames)) history_.pop_front();
    }
    if (lost_ || !config_.dynamics.propagation.enabled) {
        propagation_.clear();
    } else {
        // What this frame used (its own instances, or those carried into it); none clears.
        propagation_.store(in.segments.objects, in.frame.levels[0].depth_m);
    }
    if (in.rigid.empty()) return;
    if (lost_) {
        memory_.clear();
        return;
    }
    // The recalled pixels are kept by the memory itself (one frame older); `rigid` is what the
    // detector saw in this frame.
    memory_.store(in.rigid, in.frame.levels[0].depth_m, config_.dynamics.memory);
}

bool SlamSystem::take_late_instances(int64_t sensor_ns, const dynamics::LabelImage& objects) {
    const DynamicsOptions& d = config_.dynamics;
    if (!d.use_segments || !d.propagation.enabled || !started_ || lost_ || history_.empty() ||
        objects.empty() || objects.instances.empty() || objects.labels.size() != input_size_)
        return false;
    // Its own frame, or (a frame this system skipped to stay current) the tracked frame nearest
    // in time, within 50 ms: one camera frame's motion is what propagation carries anyway.
    const HistoryFrame* frame = nullptr;
    int64_t best = 50'000'000 + 1;
    for (const HistoryFrame& h : history_) {
        const int64_t dt = h.sensor_ns > sensor_ns ? h.sensor_ns - sensor_ns : sensor_ns - h.sensor_ns;
        if (dt < best) best = dt, frame = &h;
    }
    if (frame == nullptr) return false;
    const uint64_t last = history_.back().frame_number;
    const int age = static_cast<int>(last - frame->frame_number);
    if (age + 1 > d.propagation.max_age_frames) return false;
    const int held = propagation_.freshest_age();
    if (held >= 0 && held <= age) return false;  // what is held is as fresh
    dynamics::FrameSegments late;
    late.objects = objects;
    if (!dynamics::check(late, input_size_, "late object segments")) return false;
    late = dynamics::downscale(late, config_.system.processing_downscale);
    for (dynamics::InstanceInfo& row : late.objects.instances) row.age = age;
    const Eigen::Isometry3d last_T_stored =
        history_.back().world_T_camera.inverse() * frame->world_T_camera;
    propagation_.store(late.objects, frame->depth_m, last_T_stored.cast<float>());
    return true;
}

}  // namespace df::slam
