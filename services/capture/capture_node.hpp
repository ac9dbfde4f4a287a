#pragma once
/// The capture service's adapter: a FrameSource in, <ns>/frames out (loaned from shared memory),
/// paced in real time, flat out, or in lockstep with the stages that must see every frame.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "capture.pb.h"
#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/sample_check.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "df_msgs.h"
#include "frames_guard.hpp"
#include "io/rgbd_image.hpp"
#include "resume_state.hpp"
#include "source.hpp"
#include "stage_watch.hpp"

namespace df::capture {

struct CaptureStats {
    uint64_t published = 0;
    uint64_t bad_frames = 0;
    uint64_t lockstep_timeouts = 0;
    uint64_t loan_fallbacks = 0;
    uint64_t stages_left = 0;       ///< lockstep frames published while a required stage was gone
    uint64_t frames_abandoned = 0;  ///< lockstep waits ended because a frames reader left
    uint64_t bad_answers = 0;       ///< stage_status samples that failed check_sample
    bool resumed = false;           ///< went on after the frame a resume file recorded
    bool nothing_left = false;      ///< the resume file said the source was played to its end
    double elapsed_s = 0;
};

class CaptureNode {
  public:
    static Result<std::unique_ptr<CaptureNode>> create(const config::CaptureConfig& config,
                                                       dds::Participant& participant,
                                                       std::unique_ptr<io::FrameSource> source);
    /// Publishes until the source ends (all loops) or stop is requested. kUnavailable naming
    /// the other writer (host, pid) when another capture publishes on the same frames topic.
    /// Every wait (start, pacing, lockstep, linger) ends within 0.1 s of a stop request.
    Result<CaptureStats> run();
    /// This run's epoch (header.epoch of every frame): its start, wall clock ns.
    uint64_t epoch() const { return epoch_; }

  private:
    CaptureNode(const config::CaptureConfig& config, std::unique_ptr<io::FrameSource> source,
                dds::Writer<df_msg_RgbdFrame> frames, dds::Writer<df_msg_StageStatus> status,
                dds::Reader<df_msg_StageStatus> acks, dds::WaitSet waitset, FramesGuard guard);
    /// Refuses to start while another writer of the frames topic exists; `wait`: looks until
    /// discovery had 0.7 s since our writer was created (else looks once).
    Status check_single_writer(bool wait);
    /// Readers of our frames that have left so far (matched once, no longer matched).
    uint64_t departed_frame_readers() const;
    Status wait_for_subscribers();
    Status publish(const io::RgbdImage& image, double read_ms);
    /// The reduced JPEG colour image of the frame on <ns>/color_small.
    void publish_small(const io::RgbdImage& image, const df_msg_Header& header);
    /// Lockstep: waits until every required stage answered frame seq (or the timeout).
    void wait_for_answers(uint64_t seq);
    void collect_answers();
    /// resume_file: reads the record and moves the source after its frame. False when it says
    /// the source was played to its end already (nothing to publish).
    bool resume();
    /// resume_file: records that the frame stamped sensor_ns is done (finished: the source's end).
    void record_done(int64_t sensor_ns, bool finished);
    /// Real-time playback: sleeps until the frame is due. False when stop was requested.
    bool pace(int64_t sensor_ns);
    /// Sleeps `seconds` in slices, returning early (false) when stop is requested.
    static bool sleep_unless_stopped(double seconds);

    config::CaptureConfig config_;
    std::unique_ptr<io::FrameSource> source_;
    dds::Writer<df_msg_RgbdFrame> frames_;
    dds::Writer<df_msg_StageStatus> status_;
    std::optional<dds::Writer<df_msg_CompressedImage>> small_;  // color_small_width > 0
    dds::Reader<df_msg_StageStatus> acks_;
    dds::WaitSet waitset_;
    FramesGuard guard_;
    std::set<std::string> required_;
    std::optional<StageWatch> watch_;                    // lockstep only
    std::map<uint64_t, std::set<std::string>> answers_;  // seq -> stages that answered
    dds::RejectLog rejects_;                             // stage_status samples refused
    ResumeState resume_;                                 // resume_file's record (when set)
    uint32_t loop_ = 0;                                  // loops of the source played so far
    uint64_t seq_ = 0;
    uint64_t epoch_ = 0;
    int64_t first_sensor_ns_ = -1;
    int64_t start_wall_ns_ = 0;
    std::chrono::steady_clock::time_point created_;  // our writer's creation
    CaptureStats stats_;
};

}  // namespace df::capture
