// SlamSystem's guards against self-harm (docs/real_frames.md, "Guards"): a frame whose invalid
// mask is not to be trusted is tracked with only its persons left out, and a static map that
// died is rebuilt (the rest of the loop is in slam_system.cpp).
#include <chrono>
#include <opencv2/core.hpp>

#include "slam_system/slam_system.hpp"
#include "slam_system/stage_clock.hpp"

namespace df::slam {
cv::Mat SlamSystem::non_rigid_mask(const Input& in) {
    return dynamics::mask_of({in.instance_ids, in.segments.objects.instances},
                             {dynamics::ObjectKind::kNonRigid}, in.instance_ids.size());
}

std::string SlamSystem::guard_reason(const Input& in, const dynamics::InvalidMask& invalid) const {
    const DynamicsOptions& d = config_.dynamics;
    const bool off = d.guard_max_left_out_fraction >= 1.f && d.guard_min_model_fraction <= 0.f;
    if (off || invalid.tracking.empty()) return "";
    // Over the pixels with depth that are not a person's: what the guard would give back.
    const cv::Mat& depth = in.frame.levels[0].depth_m;
    cv::Mat with_depth = depth > 0.f;
    with_depth.setTo(0, non_rigid_mask(in));
    const int pixels = cv::countNonZero(with_depth);
    if (pixels == 0) return "";
    const int left_out = cv::countNonZero(with_depth & invalid.tracking);
    const double fraction = static_cast<double>(left_out) / pixels;
    if (d.guard_max_left_out_fraction < 1.f && fraction > d.guard_max_left_out_fraction) {
        return "the invalid mask would leave out " + std::to_string(int(100 * fraction + 0.5)) +
               " % of the frame's depth that is not a person's "
               "(dynamics.guard_max_left_out_fraction " +
               std::to_string(d.guard_max_left_out_fraction) + ")";
    }
    const cv::Mat z = static_depth();
    if (d.guard_min_model_fraction > 0.f && !z.empty() && cv::countNonZero(invalid.tracking) > 0) {
        const int model = cv::countNonZero((z > 0.f) & ~invalid.tracking);
        const double seen = static_cast<double>(model) / static_cast<double>(z.total());
        if (seen < d.guard_min_model_fraction)
            return "the static model outside the invalid mask covers " +
                   std::to_string(int(100 * seen + 0.5)) +
                   " % of the frame (dynamics.guard_min_model_fraction " +
                   std::to_string(d.guard_min_model_fraction) + ")";
    }
    return "";
}

Status SlamSystem::track_guarded(const Input& in, const Eigen::Isometry3d& guess,
                                 const cv::Mat& residual, FrameReport* report) {
    // Only the non-rigid instances (persons) stay out: what else the mask held is more likely a
    // wrong pose or a starved map than a scene that moves all at once.
    const auto t = std::chrono::steady_clock::now();
    cv::Mat persons = in.instance_ids.clone();
    persons.setTo(0, ~non_rigid_mask(in));
    // What the untrusted mask held stays out of fusion: if it was a mover after all, the map
    // does not take it in; if the pose was wrong, nothing wrong is fused at it.
    const cv::Mat fusion = report->invalid.fusion;
    report->invalid =
        dynamics::combine(in.segments, persons, cv::Mat(), residual, config_.dynamics.invalid);
    if (!fusion.empty()) report->invalid.fusion = fusion;
    const cv::Mat mask =
        cv::countNonZero(report->invalid.tracking) > 0 ? report->invalid.tracking : cv::Mat();
    Result<TrackingResult> guarded = static_.track(in.frame, guess, mask, config_.tracking);
    if (!guarded) return guarded.status();
    report->stage2 = *guarded;
    report->stage2_ran = true;
    if (guarded->state == TrackingState::kOk || report->stage1.state != TrackingState::kOk)
        report->tracking = *guarded;
    report->times.stage2_ms = ms_since(t);
    report->times.tracking_ms =
        report->times.stage1_ms + report->times.motion_ms + report->times.stage2_ms;
    static_.set_last_tracking(report->tracking);
    return Status::ok();
}

void SlamSystem::rebuild_if_needed(FrameReport* report) {
    const int after = config_.dynamics.rebuild_after_lost_frames;
    if (!started_ || after <= 0) return;
    std::string why;
    if (static_.map().size() == 0) {
        why = "the static map is empty";
    } else if (lost_run_ >= static_cast<uint64_t>(after)) {
        why = "tracking was lost " + std::to_string(lost_run_) +
              " frames in a row (dynamics.rebuild_after_lost_frames " + std::to_string(after) + ")";
    } else {
        return;
    }
    // A new static map from this frame on, at the last tracked pose: the trajectory goes on in
    // a new segment. What was learnt about the old map's frames goes with it.
    static_ = MapInstance(0, config_.map);
    started_ = false;
    lost_ = false;
    lost_run_ = 0;
    map_start_time_ = map_time_;
    last_motion_ = Eigen::Isometry3d::Identity();
    previous_motion_.release();
    history_.clear();
    memory_.clear();
    propagation_.clear();
    ++guards_.rebuilds;
    guards_.segment_starts.push_back(frames_);
    report->rebuilt = why;
}

}  // namespace df::slam
