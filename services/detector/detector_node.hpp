#pragma once
/// The detector service's adapter: <ns>/frames in; for every frame <ns>/detections (boxes, or
/// status skipped when it drops a frame to stay current or by every_nth) and <ns>/stage_status
/// out. The model is YOLO through df_detect, or the SIMULATED detector reading a generated
/// sequence's ground truth.
#include <memory>
#include <optional>
#include <vector>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/sample_check.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "boxes/box_source.hpp"
#include "detect/detector.hpp"
#include "detector.pb.h"
#include "df_msgs.h"
#include "io/rgbd_image.hpp"
#include "sim/simulated_detector.hpp"
#include "sync/seq_gaps.hpp"

namespace df::detector_service {

using boxes::BoxSource;

class DetectorNode {
  public:
    static Result<std::unique_ptr<DetectorNode>> create(const config::DetectorServiceConfig& config,
                                                        std::unique_ptr<BoxSource> source,
                                                        dds::Participant& participant);
    Status run();

  private:
    /// One frame to answer: its image (full, or the reduced colour image) and the size of the
    /// full frame the boxes are published in.
    struct Pending {
        io::RgbdImage image;
        df_msg_Header header;
        int source_width = 0, source_height = 0;
        bool valid = true;  ///< false: the sample failed its check (answered as failed)
    };
    DetectorNode(const config::DetectorServiceConfig& config, std::unique_ptr<BoxSource> source,
                 std::optional<dds::Reader<df_msg_RgbdFrame>> frames,
                 std::optional<dds::Reader<df_msg_CompressedImage>> small,
                 dds::Writer<df_msg_Detections> detections, dds::Writer<df_msg_StageStatus> status,
                 dds::WaitSet waitset);
    Status take(std::vector<Pending>* pending);
    uint32_t matched_writers() const;
    void handle(const Pending& p);
    void answer(const df_msg_Header& header, df_msg_FrameStatus status,
                const std::vector<detect::Detection>& boxes, int width, int height, double ms);
    /// Answers, as skipped, the frames of this run that never reached the reader before `p`.
    void answer_missed(const Pending& p);

    config::DetectorServiceConfig config_;
    std::unique_ptr<BoxSource> source_;
    std::optional<dds::Reader<df_msg_RgbdFrame>> frames_;
    std::optional<dds::Reader<df_msg_CompressedImage>> small_;
    dds::Writer<df_msg_Detections> detections_;
    dds::Writer<df_msg_StageStatus> status_;
    dds::WaitSet waitset_;
    dds::RejectLog rejects_;
    sync::SeqGaps gaps_;
    uint64_t detected_ = 0, skipped_ = 0, failed_ = 0;
};

}  // namespace df::detector_service
