#pragma once
/// The capture service's adapter: a FrameSource in, <ns>/frames out (loaned from shared memory),
/// paced in real time, flat out, or in lockstep with the stages that must see every frame.
#include <cstdint>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <string>

#include "capture.pb.h"
#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "io/rgbd_image.hpp"
#include "source.hpp"

namespace df::capture {

struct CaptureStats {
    uint64_t published = 0;
    uint64_t bad_frames = 0;
    uint64_t lockstep_timeouts = 0;
    uint64_t loan_fallbacks = 0;
    double elapsed_s = 0;
};

class CaptureNode {
  public:
    static Result<std::unique_ptr<CaptureNode>> create(const config::CaptureConfig& config,
                                                       dds::Participant& participant,
                                                       std::unique_ptr<io::FrameSource> source);
    /// Publishes until the source ends (all loops) or stop is requested.
    Result<CaptureStats> run();

  private:
    CaptureNode(const config::CaptureConfig& config, std::unique_ptr<io::FrameSource> source,
                dds::Writer<df_msg_RgbdFrame> frames, dds::Writer<df_msg_StageStatus> status,
                dds::Reader<df_msg_StageStatus> acks, dds::WaitSet waitset);
    Status wait_for_subscribers();
    Status publish(const io::RgbdImage& image, double read_ms);
    /// The reduced JPEG colour image of the frame on <ns>/color_small.
    void publish_small(const io::RgbdImage& image, const df_msg_Header& header);
    /// Lockstep: waits until every required stage answered frame seq (or the timeout).
    void wait_for_answers(uint64_t seq);
    void collect_answers();
    void pace(int64_t sensor_ns);

    config::CaptureConfig config_;
    std::unique_ptr<io::FrameSource> source_;
    dds::Writer<df_msg_RgbdFrame> frames_;
    dds::Writer<df_msg_StageStatus> status_;
    std::optional<dds::Writer<df_msg_CompressedImage>> small_;  // color_small_width > 0
    dds::Reader<df_msg_StageStatus> acks_;
    dds::WaitSet waitset_;
    std::set<std::string> required_;
    std::map<uint64_t, std::set<std::string>> answers_;  // seq -> stages that answered
    uint64_t seq_ = 0;
    int64_t first_sensor_ns_ = -1;
    int64_t start_wall_ns_ = 0;
    CaptureStats stats_;
};

}  // namespace df::capture
