#pragma once
/// Lockstep's view of the stages that must answer every frame: which of them are still there.
/// A stage is known by the stage_status writer its answers came from (the sample's publication
/// handle) and by its participant; it has left when that writer is no longer matched by our
/// stage_status reader, or when its participant, which had a reader of our frames topic, no
/// longer has one (process killed, stopped with SIGTERM, or its frame reader closed). Stages
/// that do not read the frames (fusion) are known by their writer only. It is waited for again
/// as soon as a reader of the frames appears in a participant first seen after the stage's last
/// answer (a restarted process, still starting up), or when it answers again; an adopted reader
/// that does not answer within the lockstep timeout (on_timeout) is not adopted again.
#include <dds/dds.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>

namespace df::capture {

class StageWatch {
  public:
    /// frames_writer: our <ns>/frames writer; acks_reader: our <ns>/stage_status reader.
    StageWatch(std::set<std::string> required, dds_entity_t frames_writer,
               dds_entity_t acks_reader);

    /// An answer of `stage` arrived from the writer `publication` (dds_sample_info_t's
    /// publication_handle). Logs when a stage that had left is back.
    void on_answer(const std::string& stage, dds_instance_handle_t publication);
    /// `stage` did not answer within the lockstep timeout: if it was waited for only because a
    /// new reader appeared, that reader is not taken for it again.
    void on_timeout(const std::string& stage);
    /// Re-reads the matched endpoints; logs each stage that left (once per departure).
    void refresh();
    /// The required stages lockstep waits for now (required minus those that left).
    const std::set<std::string>& waited() const { return waited_; }
    bool left(const std::string& stage) const { return waited_.count(stage) == 0U; }

  private:
    struct Known {
        dds_instance_handle_t writer = 0;       // its stage_status writer (0: adopted, none yet)
        dds_instance_handle_t participant = 0;  // that writer's participant
        uint64_t last_answer_tick = 0;          // refresh count at its last answer
        bool reads_frames = false;  // its participant had a frames reader (not e.g. fusion)
    };
    /// A reader participant that may be `stage` restarted (nullopt: none).
    dds_instance_handle_t candidate(const std::string& stage,
                                    const std::set<dds_instance_handle_t>& readers) const;
    std::set<dds_instance_handle_t> matched_status_writers() const;
    std::set<dds_instance_handle_t> frame_reader_participants() const;

    std::set<std::string> required_;
    dds_entity_t frames_writer_;
    dds_entity_t acks_reader_;
    std::map<std::string, Known> known_;
    std::set<std::string> waited_;
    uint64_t tick_ = 0;                                     // refresh() calls
    std::map<dds_instance_handle_t, uint64_t> first_seen_;  // reader participant -> tick
    std::set<dds_instance_handle_t> rejected_;              // adopted, never answered
};

}  // namespace df::capture
