#pragma once
/// The fusion service's adapter: joins <ns>/geometric_segments and <ns>/detections by sequence
/// number (sync::FrameJoin: a detection deadline, reuse of recent boxes), fuses boxes and
/// segments into instance masks (seg::segment_instances) and publishes <ns>/object_segments and
/// <ns>/stage_status for every frame, stating whether detections were used and whose.
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/sample_check.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "fusion.pb.h"
#include "seg/instance_segmentation.hpp"
#include "sync/frame_join.hpp"
#include "sync/seq_gaps.hpp"

namespace df::fusion_service {

struct FusionSettings {
    sync::JoinConfig join;
    seg::InstanceSegmentationConfig instance;
    params::fusion::ClassParams classes;
};

/// The settings a service configuration asks for; an error names a bad value.
Result<FusionSettings> settings_from(const config::FusionServiceConfig& config);

class FusionNode {
  public:
    static Result<std::unique_ptr<FusionNode>> create(const config::FusionServiceConfig& config,
                                                      const FusionSettings& settings,
                                                      dds::Participant& participant);
    /// Runs until stop is requested or (exit_at_end) the segment writers leave.
    Status run();

  private:
    struct Segments {
        df_msg_Header header;
        cv::Mat labels;  // CV_32SC1
        int count = 0;
    };
    FusionNode(const config::FusionServiceConfig& config, const FusionSettings& settings,
               dds::Reader<df_msg_GeometricSegments> segments,
               dds::Reader<df_msg_Detections> detections,
               dds::Writer<df_msg_ObjectSegments> objects, dds::Writer<df_msg_StageStatus> status,
               dds::WaitSet waitset);
    Status take(int64_t now);
    /// The run epoch of a message: false for an earlier run's (dropped); a later run's first
    /// message publishes the old run's waiting frames and forgets its payloads.
    bool admit(const df_msg_Header& header, int64_t now);
    void publish(const sync::JoinDecision& d);
    /// Fuses `boxes` (none when null) with the segments and writes one object_segments sample
    /// (and its stage_status); counts it unless `late` (a frame published again).
    /// `detections_seq`: whose boxes.
    void write(const Segments& seg, sync::Arrival segments_arrival,
               const std::vector<detect::Detection>* boxes, uint64_t seq, uint64_t detections_seq,
               const std::string& why, bool late = false);
    /// The frame `seq` published without its own detections, published again with them
    /// (config republish_late_ms), if its segments are still kept.
    void republish(uint64_t seq);

    config::FusionServiceConfig config_;
    FusionSettings settings_;
    dds::Reader<df_msg_GeometricSegments> segments_in_;
    dds::Reader<df_msg_Detections> detections_in_;
    dds::Writer<df_msg_ObjectSegments> objects_;
    dds::Writer<df_msg_StageStatus> status_;
    dds::WaitSet waitset_;
    dds::RejectLog rejects_;  ///< samples that failed their check
    sync::FrameJoin join_;
    sync::SeqGaps segment_gaps_;  ///< geometric segments this reader never received
    std::map<uint64_t, Segments> segments_;
    std::map<uint64_t, std::vector<detect::Detection>> detections_;
    /// Frames published without their own detections, kept for republish_late_ms.
    std::map<uint64_t, Segments> published_without_;
    uint64_t republished_ = 0;
    uint64_t published_ = 0, with_own_ = 0, with_reused_ = 0, without_ = 0;
    uint64_t future_epochs_ = 0;  // messages dropped for an epoch far in the future
    std::map<std::string, uint64_t> instances_by_class_;  // over the stream, for the end log
};

}  // namespace df::fusion_service
