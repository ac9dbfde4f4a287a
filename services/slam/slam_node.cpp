#include "slam_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "io/tum/trajectory.hpp"
#include "service/service.hpp"
#include "slam_system/checkpoint.hpp"

namespace df::slam_service {
namespace {

/// History of the object_segments and geometric_segments readers (messages kept until taken).
constexpr int32_t kCompanionDepth = 64;

int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

}  // namespace

Result<std::unique_ptr<SlamNode>> SlamNode::create(const config::SlamServiceConfig& config,
                                                   const slam::SystemConfig& system_config,
                                                   dds::Participant& participant,
                                                   std::atomic<bool>* save_request) {
    const std::string& ns = config.dds().ns();
    auto frames = dds::Reader<df_msg_RgbdFrame>::create(participant,
                                                        dds::topic_name(ns, dds::topics::kFrames));
    if (!frames) return frames.status();
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(frames->get()));
    std::optional<dds::Reader<df_msg_ObjectSegments>> objects;
    std::optional<dds::Reader<df_msg_GeometricSegments>> geometric;
    if (config.use_segments()) {
        // Deep enough for a burst: fusion releases every waiting frame at once when the
        // detector leaves (up to its max_pending, 30).
        const dds::EndpointOptions companions{dds::QosProfile::kResults, kCompanionDepth};
        auto o = dds::Reader<df_msg_ObjectSegments>::create(
            participant, dds::topic_name(ns, dds::topics::kObjectSegments), companions);
        if (!o) return o.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(o->get()));
        objects.emplace(std::move(*o));
        auto g = dds::Reader<df_msg_GeometricSegments>::create(
            participant, dds::topic_name(ns, dds::topics::kGeometricSegments), companions);
        if (!g) return g.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(g->get()));
        geometric.emplace(std::move(*g));
    }
    auto poses = dds::Writer<df_msg_CameraPose>::create(
        participant, dds::topic_name(ns, dds::topics::kCameraPose));
    if (!poses) return poses.status();
    std::optional<dds::Writer<df_msg_ObjectSegments>> invalid;
    if (config.publish_invalid_mask()) {
        auto w = dds::Writer<df_msg_ObjectSegments>::create(
            participant, dds::topic_name(ns, dds::topics::kInvalidMask));
        if (!w) return w.status();
        invalid.emplace(std::move(*w));
    }
    auto object_poses = dds::Writer<df_msg_ObjectPoses>::create(
        participant, dds::topic_name(ns, dds::topics::kObjectPoses));
    if (!object_poses) return object_poses.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    std::unique_ptr<SlamNode> node(new SlamNode(
        config, system_config, std::move(*frames), std::move(objects), std::move(geometric),
        std::move(*poses), std::move(invalid), std::move(*object_poses), std::move(*status),
        std::move(*waitset), save_request));
    if (config.map_cloud_every_frames() > 0) {
        auto w = dds::Writer<df_msg_MapCloud>::create(participant,
                                                      dds::topic_name(ns, dds::topics::kMapCloud));
        if (!w) return w.status();
        node->map_cloud_.emplace(std::move(*w));
    }
    return node;
}

SlamNode::SlamNode(const config::SlamServiceConfig& config, const slam::SystemConfig& system_config,
                   dds::Reader<df_msg_RgbdFrame> frames,
                   std::optional<dds::Reader<df_msg_ObjectSegments>> objects,
                   std::optional<dds::Reader<df_msg_GeometricSegments>> geometric,
                   dds::Writer<df_msg_CameraPose> poses,
                   std::optional<dds::Writer<df_msg_ObjectSegments>> invalid,
                   dds::Writer<df_msg_ObjectPoses> object_poses,
                   dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset,
                   std::atomic<bool>* save_request)
    : config_(config),
      system_config_(system_config),
      frames_(std::move(frames)),
      objects_(std::move(objects)),
      geometric_(std::move(geometric)),
      poses_(std::move(poses)),
      invalid_(std::move(invalid)),
      object_poses_(std::move(object_poses)),
      status_(std::move(status)),
      waitset_(std::move(waitset)),
      join_(2, static_cast<int64_t>(config.segments_deadline_ms() * 1e6),
            /*max_pending=*/30),
      save_request_(save_request) {}

bool SlamNode::resume_from_checkpoint() {
    const std::string& dir = config_.output().dir();
    if (dir.empty() || !config_.resume()) return false;
    const std::string file = dir + "/checkpoint.bin";
    const std::string trajectory = dir + "/trajectory.txt";
    auto checkpoint = slam::read_checkpoint(file);
    if (!checkpoint) {
        if (checkpoint.status().code() == StatusCode::kNotFound) return false;
        std::error_code ec;
        const std::string kept = dir + "/trajectory.before-restart.txt";
        std::filesystem::rename(trajectory, kept, ec);
        log::error(checkpoint.status().message(), "; ignored, starting with an empty map",
                   ec ? "" : " (the earlier trajectory is kept as " + kept + ")");
        return false;
    }
    slam::SystemState& state = checkpoint->system;
    // Poses appended after the checkpoint was taken were estimated too: keep them.
    const double last_s = state.trajectory.empty() ? -1.0 : state.trajectory.back().stamp_s;
    size_t carried = 0;
    if (auto appended = io::read_tum_trajectory(trajectory)) {
        for (const io::StampedPose& p : appended->poses) {
            if (p.stamp_s <= last_s + 0.5e-6) continue;  // the file has microseconds
            state.trajectory.push_back(p);
            ++carried;
        }
    }
    int64_t after_ns = checkpoint->last_sensor_ns;
    if (carried > 0) {
        after_ns = std::max(
            after_ns, static_cast<int64_t>(std::llround(state.trajectory.back().stamp_s * 1e9)));
    }
    const size_t surfels = state.surfels.size();
    auto system = slam::SlamSystem::restore(system_config_, std::move(state));
    if (!system) {
        log::error("checkpoint '", file, "': ", system.status().message(),
                   "; ignored, starting with an empty map");
        return false;
    }
    system_.emplace(std::move(*system));
    auto outputs = RunOutputs::open(dir, true);
    if (!outputs) {
        log::error(outputs.status().message());
        return false;
    }
    outputs_.emplace(std::move(*outputs));
    resume_after_ns_ = after_ns;
    have_last_ = true;
    last_seq_ = checkpoint->last_seq;
    last_epoch_ = checkpoint->last_epoch;
    last_sensor_ns_ = checkpoint->last_sensor_ns;
    log::info("resumed from checkpoint at seq ", checkpoint->last_seq, " (", surfels, " surfels), ",
              system_->trajectory().size(), " poses (", carried,
              " of them appended to trajectory.txt after the checkpoint)");
    return true;
}

Status SlamNode::start_stream() {
    if (!resume_from_checkpoint()) {
        auto system = slam::SlamSystem::create(system_config_);
        if (!system) return system.status();
        system_.emplace(std::move(*system));
        if (!config_.output().dir().empty()) {
            auto outputs = RunOutputs::open(config_.output().dir());
            if (!outputs) return outputs.status();
            outputs_.emplace(std::move(*outputs));
        }
    }
    stream_start_ns_ = now_ns();
    last_checkpoint_ns_ = 0;  // none yet: the first frame's state is saved at once
    skipped_ = failed_ = tracked_before_ = late_segments_ = late_instances_taken_ = 0;
    was_lost_ = false;
    log::info("stream started");
    return Status::ok();
}

bool SlamNode::already_tracked(const df_msg_Header& header) {
    if (have_last_ && header.epoch != last_epoch_) {
        // A restarted capture plays its source again: go on with the same map and trajectory.
        resume_after_ns_ = std::max(resume_after_ns_, last_sensor_ns_);
        log::info("seq=", header.seq, " a new capture run (epoch ", header.epoch,
                  "): the map goes on; frames up to the last tracked one are answered skipped");
    }
    have_last_ = true;
    last_epoch_ = header.epoch;
    if (resume_after_ns_ < 0) return false;
    if (static_cast<int64_t>(header.sensor_ns) <= resume_after_ns_) return true;
    log::info("seq=", header.seq, " tracking on after the restart (", tracked_before_,
              " frame(s) tracked before it answered skipped)");
    resume_after_ns_ = -1;
    return false;
}

void SlamNode::checkpoint(bool now) {
    if (!system_ || !outputs_ || !have_last_) return;
    const double every_s = config_.checkpoint_s();
    // The first checkpoint comes with the first frame, so a service killed in its first
    // checkpoint_s resumes (keeping its poses) instead of starting a new map.
    const bool first = last_checkpoint_ns_ == 0;
    const double since_s = static_cast<double>(now_ns() - last_checkpoint_ns_) * 1e-9;
    if (!now && (every_s <= 0 || (!first && since_s < every_s))) return;
    last_checkpoint_ns_ = now_ns();
    slam::Checkpoint c;
    c.system = system_->state();
    c.last_seq = last_seq_;
    c.last_epoch = last_epoch_;
    c.last_sensor_ns = last_sensor_ns_;
    if (Status s = slam::write_checkpoint(outputs_->checkpoint_file(), c); !s) {
        log::error("seq=", last_seq_, " ", s.message());
    } else {
        log::debug("seq=", last_seq_, " checkpoint written (", c.system.surfels.size(),
                   " surfels)");
    }
}

namespace {
/// "p50 41.2 ms, p99 80.3 ms, max 95.0 ms" (or "none").
std::string latency_text(std::vector<double> ms) {
    if (ms.empty()) return "none";
    std::sort(ms.begin(), ms.end());
    const auto at = [&ms](double q) {
        return ms[std::min(ms.size() - 1, static_cast<size_t>(q * static_cast<double>(ms.size())))];
    };
    char text[96];
    std::snprintf(text, sizeof text, "p50 %.1f ms, p99 %.1f ms, max %.1f ms", at(0.5), at(0.99),
                  ms.back());
    return text;
}
}  // namespace

Status SlamNode::end_stream(const char* why) {
    if (!system_) return Status::ok();
    const double wall_s = static_cast<double>(last_frame_ns_ - stream_start_ns_) * 1e-9;
    log::info("stream ended (", why, "): ", system_->frames(), " frames processed, ",
              system_->lost_frames(), " lost, ", skipped_, " skipped to stay current, ", failed_,
              " failed; ", late_segments_, " tracked past the segments deadline, ",
              late_instances_taken_, " late object segments carried forward; map ",
              system_->static_map().size(), " surfels; capture to pose of the tracked frames ",
              latency_text(pose_latency_ms_));
    pose_latency_ms_.clear();
    Status written = Status::ok();
    checkpoint(true);  // a service started again later goes on from here
    if (outputs_) {
        written = outputs_->finish(*system_, config_.output().stable_only(), wall_s);
        if (written) {
            log::info("wrote ", outputs_->trajectory_file(), ", ", outputs_->map_file(), ", ",
                      outputs_->summary_file());
        }
    }
    system_.reset();
    outputs_.reset();
    return written;
}

void SlamNode::answer_unprocessed(const df_msg_Header& header, df_msg_FrameStatus status) {
    df_msg_CameraPose pose{};
    pose.header = header;
    pose.header.status = status;
    pose.state = df_msg_TRACKING_LOST;
    pose.world_T_camera.qw = 1.0;
    (void)poses_.write_copy(pose);
    df_msg_StageStatus answer{};
    answer.header = pose.header;
    dds::set_name(answer.stage, config_.stage());
    (void)status_.write_copy(answer);
}

void SlamNode::handle(const io::RgbdImage& image, const df_msg_Header& header,
                      const dynamics::FrameSegments& segments, const std::string& segments_note) {
    if (already_tracked(header)) {
        ++tracked_before_;
        answer_unprocessed(header, df_msg_FRAME_SKIPPED);
        return;
    }
    const size_t poses_before = system_->trajectory().size();
    auto report = system_->process(image, segments);
    if (!report) {
        ++failed_;
        log::error("seq=", header.seq, " frame not processed: ", report.status().message());
        answer_unprocessed(header, df_msg_FRAME_FAILED);
        return;
    }
    if (!segments_note.empty()) log::warn("seq=", header.seq, " ", segments_note);
    if (!report->segments_error.empty())
        log::warn("seq=", header.seq, " segments not used: ", report->segments_error);
    const slam::TrackingResult& t = report->tracking;
    const bool lost = t.state == slam::TrackingState::kLost;
    if (lost && !was_lost_) log::warn("seq=", header.seq, " tracking lost: ", t.reason);
    if (!lost && was_lost_) log::info("seq=", header.seq, " tracking recovered");
    was_lost_ = lost;
    const uint32_t every = config_.output().log_every();
    if (every > 0 && header.seq % every == 0) {
        log::info("seq=", header.seq, " ", slam::to_string(t.state), " inliers=", t.inlier_ratio,
                  " icp_rmse_mm=", t.icp_rmse_m * 1000, " surfels=", report->fusion.total,
                  " fused=", report->fusion.fused, " created=", report->fusion.created,
                  " removed=", report->fusion.removed + report->fusion.removed_free_space,
                  " instances=", report->instances.instances.size(),
                  " detections_age=", report->detections_age, " carried=", report->carried,
                  " motion_px=", report->motion.mask_pixels,
                  " stage2=", report->stage2_ran ? slam::to_string(report->stage2.state) : "no",
                  " total_ms=", report->times.total_ms);
    }

    // The pose goes to trajectory.txt before anything is published: a capture records the frame
    // done once SLAM answered it, so a SLAM killed between its answer and this write (a heal's
    // SIGKILL of a SLAM blocked in a stuck RouDi) would lose the pose for good.
    if (outputs_) {
        outputs_->add(header.seq, *report);
        if (system_->trajectory().size() > poses_before)
            outputs_->append_pose(system_->trajectory().back());
    }

    df_msg_CameraPose pose{};
    pose.header = header;
    pose.header.status = df_msg_FRAME_OK;
    pose.world_T_camera = dds::to_pose_msg(report->world_T_camera);
    pose.state = report->first ? df_msg_TRACKING_INITIALIZING
                               : (lost ? df_msg_TRACKING_LOST : df_msg_TRACKING_OK);
    pose.inlier_ratio = t.inlier_ratio;
    pose.residual = t.icp_rmse_m;
    if (Status s = poses_.write_copy(pose); !s) log::warn("seq=", header.seq, " ", s.message());
    if (header.capture_ns > 0 && pose_latency_ms_.size() < 1'000'000)
        pose_latency_ms_.push_back(
            static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count() -
                                static_cast<int64_t>(header.capture_ns)) *
            1e-6);
    publish_invalid(pose.header, *report, image.depth.size());
    publish_objects(pose.header, *report);
    publish_map_cloud(pose.header);

    df_msg_StageStatus answer{};
    answer.header = pose.header;
    dds::set_name(answer.stage, config_.stage());
    const auto steps = report->times.steps();
    answer.timing_count = 0;
    for (const auto& [name, ms] : steps) {
        if (answer.timing_count >= df_msg_MAX_STAGE_TIMINGS) break;
        df_msg_StageTiming& timing = answer.timings[answer.timing_count++];
        dds::set_name(timing.name, name);
        timing.ms = static_cast<float>(ms);
    }
    if (Status s = status_.write_copy(answer); !s) log::warn("seq=", header.seq, " ", s.message());
    last_seq_ = header.seq;
    last_sensor_ns_ = static_cast<int64_t>(header.sensor_ns);
    checkpoint(false);
}

Status SlamNode::run() {
    log::info("waiting for frames on ", frames_.topic(),
              objects_ ? " with object_segments and geometric_segments (deadline " +
                             std::to_string(config_.segments_deadline_ms()) + " ms)"
                       : std::string(" (segments not used)"));
    service::StreamEnd stream(config_.idle_exit_s(), config_.writers_grace_s());
    while (!service::stop_requested()) {
        auto woke = waitset_.wait(DDS_MSECS(20));
        if (!woke) return woke.status();
        size_t frames_taken = 0;
        DF_RETURN_IF_ERROR(take_inputs(&frames_taken));
        std::vector<sync::CompanionJoin::Ready> ready = join_.poll(now_ns());
        // Stay current (a live camera): answer older ready frames as skipped, track the newest.
        // Without stay_current (recorded sequences) every ready frame is tracked.
        for (size_t i = 0; i < ready.size(); ++i) {
            auto it = waiting_.find(ready[i].seq);
            if (it == waiting_.end()) continue;
            PendingFrame frame = std::move(it->second);
            waiting_.erase(it);
            if (!system_) DF_RETURN_IF_ERROR(start_stream());
            last_frame_ns_ = now_ns();
            stream.on_input();
            if (config_.stay_current() && i + 1 < ready.size()) {
                ++skipped_;
                answer_unprocessed(frame.header, df_msg_FRAME_SKIPPED);
                continue;
            }
            dynamics::FrameSegments segments;
            const uint64_t seq = ready[i].seq;
            if (auto o = objects_in_.find(seq); o != objects_in_.end()) {
                segments.objects = std::move(o->second.first);
                segments.detections_age = o->second.second;
                objects_in_.erase(o);
            } else if (objects_) {
                segments.detections_age = -1;  // none in time: the last instances are carried
            }
            if (auto g = geometric_in_.find(seq); g != geometric_in_.end()) {
                segments.geometric = g->second.first;
                segments.geometric_count = g->second.second;
                geometric_in_.erase(g);
            }
            std::string note;
            if (ready[i].late) {
                ++late_segments_;
                note = std::string(ready[i].ok[0] ? "" : "object_segments") +
                       (ready[i].ok[0] || ready[i].ok[1] ? "" : " and ") +
                       (ready[i].ok[1] ? "" : "geometric_segments") + " not here within " +
                       std::to_string(config_.segments_deadline_ms()) +
                       " ms: tracked with what arrived (motion segmentation alone without "
                       "object segments)";
            }
            handle(frame.image, frame.header, segments, note);
        }
        if (frames_taken > 0) stream.on_input();
        if (save_request_ != nullptr && save_request_->exchange(false) && system_ && outputs_) {
            const double wall_s = static_cast<double>(last_frame_ns_ - stream_start_ns_) * 1e-9;
            if (Status s = outputs_->finish(*system_, config_.output().stable_only(), wall_s); !s)
                log::error(s.message());
            else
                log::info("outputs written on request to ", outputs_->dir());
        }
        if (const char* why =
                stream.check(frames_.matched_writers(), frames_taken == 0 && waiting_.empty())) {
            stream.reset();
            DF_RETURN_IF_ERROR(end_stream(why));
            if (config_.exit_at_end()) return Status::ok();
        }
    }
    return end_stream("stop requested");
}

}  // namespace df::slam_service
