#include "slam_node.hpp"

#include <chrono>
#include <vector>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "service/service.hpp"

namespace df::slam_service {
namespace {

int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

df_msg_Pose to_msg(const Eigen::Isometry3d& pose) {
    const Eigen::Quaterniond q(pose.linear());
    return df_msg_Pose{pose.translation().x(),
                       pose.translation().y(),
                       pose.translation().z(),
                       q.x(),
                       q.y(),
                       q.z(),
                       q.w()};
}

struct Pending {
    io::RgbdImage image;
    df_msg_Header header;
};

}  // namespace

Result<std::unique_ptr<SlamNode>> SlamNode::create(const config::SlamServiceConfig& config,
                                                   const slam::SystemConfig& system_config,
                                                   dds::Participant& participant,
                                                   std::atomic<bool>* save_request) {
    const std::string& ns = config.dds().ns();
    auto frames = dds::Reader<df_msg_RgbdFrame>::create(participant,
                                                        dds::topic_name(ns, dds::topics::kFrames));
    if (!frames) return frames.status();
    auto poses = dds::Writer<df_msg_CameraPose>::create(
        participant, dds::topic_name(ns, dds::topics::kCameraPose));
    if (!poses) return poses.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(frames->get()));
    return std::unique_ptr<SlamNode>(new SlamNode(config, system_config, std::move(*frames),
                                                  std::move(*poses), std::move(*status),
                                                  std::move(*waitset), save_request));
}

SlamNode::SlamNode(const config::SlamServiceConfig& config, const slam::SystemConfig& system_config,
                   dds::Reader<df_msg_RgbdFrame> frames, dds::Writer<df_msg_CameraPose> poses,
                   dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset,
                   std::atomic<bool>* save_request)
    : config_(config),
      system_config_(system_config),
      frames_(std::move(frames)),
      poses_(std::move(poses)),
      status_(std::move(status)),
      waitset_(std::move(waitset)),
      save_request_(save_request) {}

Status SlamNode::start_stream() {
    auto system = slam::SlamSystem::create(system_config_);
    if (!system) return system.status();
    system_.emplace(std::move(*system));
    if (!config_.output().dir().empty()) {
        auto outputs = RunOutputs::open(config_.output().dir());
        if (!outputs) return outputs.status();
        outputs_.emplace(std::move(*outputs));
    }
    stream_start_ns_ = now_ns();
    skipped_ = failed_ = 0;
    was_lost_ = false;
    log::info("stream started");
    return Status::ok();
}

Status SlamNode::end_stream(const char* why) {
    if (!system_) return Status::ok();
    const double wall_s = static_cast<double>(last_frame_ns_ - stream_start_ns_) * 1e-9;
    log::info("stream ended (", why, "): ", system_->frames(), " frames processed, ",
              system_->lost_frames(), " lost, ", skipped_, " skipped to stay current, ", failed_,
              " failed; map ", system_->static_map().size(), " surfels");
    Status written = Status::ok();
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

void SlamNode::handle(const io::RgbdImage& image, const df_msg_Header& header) {
    auto report = system_->process(image);
    if (!report) {
        ++failed_;
        log::error("seq=", header.seq, " frame not processed: ", report.status().message());
        answer_unprocessed(header, df_msg_FRAME_FAILED);
        return;
    }
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
                  " total_ms=", report->times.total_ms);
    }

    df_msg_CameraPose pose{};
    pose.header = header;
    pose.header.status = df_msg_FRAME_OK;
    pose.world_T_camera = to_msg(report->world_T_camera);
    pose.state = report->first ? df_msg_TRACKING_INITIALIZING
                               : (lost ? df_msg_TRACKING_LOST : df_msg_TRACKING_OK);
    pose.inlier_ratio = t.inlier_ratio;
    pose.residual = t.icp_rmse_m;
    if (Status s = poses_.write_copy(pose); !s) log::warn("seq=", header.seq, " ", s.message());

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
    if (outputs_) outputs_->add(header.seq, *report);
}

Status SlamNode::run() {
    log::info("waiting for frames on ", frames_.topic());
    service::StreamEnd stream(config_.idle_exit_s());
    while (!service::stop_requested()) {
        auto woke = waitset_.wait(DDS_MSECS(100));
        if (!woke) return woke.status();
        std::vector<Pending> pending;
        auto taken = frames_.take(
            [&](const df_msg_RgbdFrame& f, const dds_sample_info_t& info) {
                if (!info.valid_data) return;
                pending.push_back({dds::to_image(f), f.header});
            },
            16);
        if (!taken) return taken.status();
        // Stay current: answer older frames as skipped, process the newest.
        for (size_t i = 0; i < pending.size(); ++i) {
            if (!system_) DF_RETURN_IF_ERROR(start_stream());
            last_frame_ns_ = now_ns();
            stream.on_input();
            if (i + 1 < pending.size()) {
                ++skipped_;
                answer_unprocessed(pending[i].header, df_msg_FRAME_SKIPPED);
            } else {
                handle(pending[i].image, pending[i].header);
            }
        }
        if (save_request_ != nullptr && save_request_->exchange(false) && system_ && outputs_) {
            const double wall_s = static_cast<double>(last_frame_ns_ - stream_start_ns_) * 1e-9;
            if (Status s = outputs_->finish(*system_, config_.output().stable_only(), wall_s); !s)
                log::error(s.message());
            else
                log::info("outputs written on request to ", outputs_->dir());
        }
        if (const char* why = stream.check(frames_.matched_writers(), pending.empty())) {
            stream.reset();
            DF_RETURN_IF_ERROR(end_stream(why));
            if (config_.exit_at_end()) return Status::ok();
        }
    }
    return end_stream("stop requested");
}

}  // namespace df::slam_service
