#pragma once
/// The geometric segmentation service's adapter: <ns>/frames in; for every frame
/// <ns>/geometric_segments (label image, or status skipped/failed with no labels) and
/// <ns>/stage_status (timings; capture's lockstep answer) out. Frames that pile up while it works
/// are answered as skipped and the newest is processed; frames the reader lost (a full history
/// over shared memory) are answered as skipped too.
#include <memory>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/sample_check.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "geoseg.pb.h"
#include "io/rgbd_image.hpp"
#include "seg/geometric_segmentation.hpp"
#include "slam/slam_config.hpp"
#include "sync/seq_gaps.hpp"

namespace df::geoseg_service {

/// The library configurations a service configuration asks for (defaults where it is silent).
Status apply(const config::GeosegParams& params, seg::GeometricSegmentationConfig* seg,
             slam::PreprocessConfig* preprocess);

class GeosegNode {
  public:
    static Result<std::unique_ptr<GeosegNode>> create(const config::GeosegServiceConfig& config,
                                                      const seg::GeometricSegmentationConfig& seg,
                                                      const slam::PreprocessConfig& preprocess,
                                                      dds::Participant& participant);
    /// Runs until stop is requested or (exit_at_end) the stream ends.
    Status run();

  private:
    GeosegNode(const config::GeosegServiceConfig& config,
               const seg::GeometricSegmentationConfig& seg,
               const slam::PreprocessConfig& preprocess, dds::Reader<df_msg_RgbdFrame> frames,
               dds::Writer<df_msg_GeometricSegments> segments,
               dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset);
    void handle(const io::RgbdImage& image, const df_msg_Header& header);
    void answer(const df_msg_Header& header, df_msg_FrameStatus status);
    /// Answers, as skipped, the frames of this run that never reached the reader before `header`.
    void answer_missed(const df_msg_Header& header);

    config::GeosegServiceConfig config_;
    seg::GeometricSegmentationConfig seg_;
    slam::PreprocessConfig preprocess_;
    dds::Reader<df_msg_RgbdFrame> frames_;
    dds::Writer<df_msg_GeometricSegments> segments_;
    dds::Writer<df_msg_StageStatus> status_;
    dds::WaitSet waitset_;
    dds::RejectLog rejects_;
    sync::SeqGaps gaps_;
    uint64_t processed_ = 0, skipped_ = 0, failed_ = 0;
};

}  // namespace df::geoseg_service
