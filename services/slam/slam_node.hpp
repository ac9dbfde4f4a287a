#pragma once
/// The SLAM service's adapter: <ns>/frames, <ns>/object_segments and <ns>/geometric_segments in,
/// joined by sequence number (sync::CompanionJoin: a frame waits at most segments_deadline_ms for
/// its segments, then is tracked with motion segmentation alone); per frame <ns>/camera_pose
/// (pose, tracking state, figures), <ns>/object_poses (every object map's pose),
/// <ns>/invalid_mask (what was left out of the static map) and
/// <ns>/stage_status (stage timings, also capture's lockstep answer) out. Writes
/// trajectory, map, timings and summary when the stream ends, on SIGUSR1, and at stop; appends
/// each tracked pose to trajectory.txt as it goes and checkpoints its state every checkpoint_s.
///
/// Restarts: a service that finds <output.dir>/checkpoint.bin (resume: true) goes on from it
/// (map, pose, trajectory, plus the poses appended to trajectory.txt after the checkpoint) and
/// answers frames it has already tracked (sensor stamp not after the last one) as skipped; a new
/// capture run (header.epoch) continues the same map and trajectory the same way.
#include <atomic>
#include <map>
#include <memory>
#include <optional>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/sample_check.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "run_outputs.hpp"
#include "slam.pb.h"
#include "slam_system/slam_system.hpp"
#include "sync/companion_join.hpp"
#include "sync/seq_gaps.hpp"

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
    /// One frame waiting for its segments.
    struct PendingFrame {
        io::RgbdImage image;
        df_msg_Header header;
    };
    SlamNode(const config::SlamServiceConfig& config, const slam::SystemConfig& system_config,
             dds::Reader<df_msg_RgbdFrame> frames,
             std::optional<dds::Reader<df_msg_ObjectSegments>> objects,
             std::optional<dds::Reader<df_msg_GeometricSegments>> geometric,
             dds::Writer<df_msg_CameraPose> poses,
             std::optional<dds::Writer<df_msg_ObjectSegments>> invalid,
             dds::Writer<df_msg_ObjectPoses> object_poses, dds::Writer<df_msg_StageStatus> status,
             dds::WaitSet waitset, std::atomic<bool>* save_request);
    /// Takes what arrived on the three inputs into the join; false when the reader failed.
    Status take_inputs(size_t* frames_taken);
    /// Processes one frame (copied out of the sample) with its segments and publishes its
    /// answers.
    void handle(const io::RgbdImage& image, const df_msg_Header& header,
                const dynamics::FrameSegments& segments, const std::string& segments_note);
    void publish_invalid(const df_msg_Header& header, const slam::FrameReport& report,
                         cv::Size frame_size);
    /// <ns>/object_poses: every live object map's pose, whether it was seen and tracked.
    void publish_objects(const df_msg_Header& header, const slam::FrameReport& report);
    /// <ns>/map_cloud every map_cloud_every_frames frames: the maps thinned, for viewing.
    void publish_map_cloud(const df_msg_Header& header);
    /// Answers a frame that was not processed (skipped to stay current, or failed).
    void answer_unprocessed(const df_msg_Header& header, df_msg_FrameStatus status);
    Status start_stream();
    /// start_stream() from the checkpoint in the output folder, when there is one (false: none,
    /// or a bad one, reported with its path; the earlier trajectory is kept aside).
    bool resume_from_checkpoint();
    /// True when the frame was tracked before a restart (service or capture): answer it skipped.
    bool already_tracked(const df_msg_Header& header);
    /// Writes the checkpoint when checkpoint_s has passed since the last one (or `now`).
    void checkpoint(bool now);
    Status end_stream(const char* why);

    config::SlamServiceConfig config_;
    slam::SystemConfig system_config_;
    dds::Reader<df_msg_RgbdFrame> frames_;
    std::optional<dds::Reader<df_msg_ObjectSegments>> objects_;
    std::optional<dds::Reader<df_msg_GeometricSegments>> geometric_;
    dds::Writer<df_msg_CameraPose> poses_;
    std::optional<dds::Writer<df_msg_ObjectSegments>> invalid_;
    dds::Writer<df_msg_ObjectPoses> object_poses_;
    std::optional<dds::Writer<df_msg_MapCloud>> map_cloud_;  ///< when map_cloud_every_frames > 0
    uint64_t frames_since_map_cloud_ = 0;
    dds::Writer<df_msg_StageStatus> status_;
    dds::WaitSet waitset_;
    dds::RejectLog rejects_;  ///< samples that failed their check
    sync::CompanionJoin join_;
    sync::SeqGaps frame_gaps_;                  ///< frames this reader never received
    std::map<uint64_t, PendingFrame> waiting_;  ///< frames in the join, by seq
    /// By seq: the instances and how old their detections are (FrameSegments::detections_age).
    std::map<uint64_t, std::pair<dynamics::LabelImage, int>> objects_in_;
    std::map<uint64_t, std::pair<cv::Mat, int>> geometric_in_;  ///< labels, count, by seq
    uint64_t join_epoch_ = 0;
    uint64_t late_segments_ = 0;
    uint64_t late_instances_taken_ = 0;    ///< late object segments propagation took
    std::vector<double> pose_latency_ms_;  ///< capture to pose published, tracked frames
    std::atomic<bool>* save_request_;
    std::optional<slam::SlamSystem> system_;
    std::optional<RunOutputs> outputs_;
    int64_t stream_start_ns_ = 0;
    int64_t last_frame_ns_ = 0;
    uint64_t skipped_ = 0, failed_ = 0;
    bool was_lost_ = false;
    int64_t last_checkpoint_ns_ = 0;
    bool have_last_ = false;  // a frame was processed: the three below are set
    uint64_t last_seq_ = 0;   // of the last frame processed
    uint64_t last_epoch_ = 0;
    int64_t last_sensor_ns_ = 0;
    int64_t resume_after_ns_ = -1;  // frames stamped up to this were tracked before a restart
    uint64_t tracked_before_ = 0;   // frames answered skipped for that
};

}  // namespace df::slam_service
