#pragma once
/// The SLAM service's adapter: <ns>/frames in; per frame <ns>/camera_pose (pose, tracking state,
/// figures) and <ns>/stage_status (stage timings, also capture's lockstep answer) out. Writes
/// trajectory, map, timings and summary when the stream ends, on SIGUSR1, and at stop.
#include <atomic>
#include <memory>
#include <optional>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "run_outputs.hpp"
#include "slam.pb.h"
#include "slam_system/slam_system.hpp"

namespace df::slam_service {

class SlamNode {
  public:
    /// save_request: set (e.g. by a SIGUSR1 handler) to write the outputs now; the node clears it.
    static Result<std::unique_ptr<SlamNode>> create(const config::SlamServiceConfig& config,
                                                    const slam::SystemConfig& system_config,
                                                    dds::Participant& participant,
                                                    std::atomic<bool>* save_request);
    /// Runs until stop is requested or (exit_at_end) the stream ends. Outputs are written at
    /// the end of each stream and at stop.
    Status run();

  private:
    SlamNode(const config::SlamServiceConfig& config, const slam::SystemConfig& system_config,
             dds::Reader<df_msg_RgbdFrame> frames, dds::Writer<df_msg_CameraPose> poses,
             dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset,
             std::atomic<bool>* save_request);
    /// Processes one frame (copied out of the sample) and publishes its answers.
    void handle(const io::RgbdImage& image, const df_msg_Header& header);
    /// Answers a frame that was not processed (skipped to stay current, or failed).
    void answer_unprocessed(const df_msg_Header& header, df_msg_FrameStatus status);
    Status start_stream();
    Status end_stream(const char* why);

    config::SlamServiceConfig config_;
    slam::SystemConfig system_config_;
    dds::Reader<df_msg_RgbdFrame> frames_;
    dds::Writer<df_msg_CameraPose> poses_;
    dds::Writer<df_msg_StageStatus> status_;
    dds::WaitSet waitset_;
    std::atomic<bool>* save_request_;
    std::optional<slam::SlamSystem> system_;
    std::optional<RunOutputs> outputs_;
    int64_t stream_start_ns_ = 0;
    int64_t last_frame_ns_ = 0;
    uint64_t skipped_ = 0, failed_ = 0;
    bool was_lost_ = false;
};

}  // namespace df::slam_service
