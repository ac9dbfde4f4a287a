#pragma once
/// The fusion service's timestamp join, as a DDS-free state machine: geometric segments and
/// detections of the same frame (sequence number, set once by capture) are paired; a frame whose
/// detections are late past a deadline is released without them, so a slow or remote detector
/// never stalls the pipeline. The caller keeps the payloads by sequence number and feeds only
/// arrivals and the clock; decisions come out in frame order.
///
/// Rules (tests/unit/sync drive them with tables of arrival times):
/// - A frame is known by its segments message. It is released when its own detections arrive
///   (ok, skipped or failed) or when `detection_deadline_ms` has passed since its segments
///   arrived, whichever is first; frames are released in sequence order (a frame waits for the
///   ones before it, which the deadline bounds).
/// - Released without its own detections, a frame uses the newest ok detections of an earlier
///   frame whose capture time is at most `reuse_max_age_ms` older (boxes move little in that
///   time); otherwise it is released without detections.
/// - Segments that were skipped or failed release the frame at once, marked so.
/// - Duplicates are ignored; messages for frames already released (late detections) are kept
///   only as candidates for reuse; detections that arrive before their segments wait for them.
/// - At most `max_pending` frames wait; beyond that the oldest is released at once.
/// - Runs: sequence numbers count from 0 again in each capture run (header.epoch, the run's
///   start). Every message is first shown to on_epoch(): a message of a later run releases the
///   frames still waiting (the old run's last decisions) and starts the join over, so no frame
///   of the new run is taken for a duplicate; a message of an earlier run is stale, ignored.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "params/fusion_params.hpp"

namespace df::sync {

enum class Arrival { kOk, kSkipped, kFailed };

/// What on_epoch() made of a message's run epoch.
enum class EpochCheck {
    kCurrent,  ///< the run being joined: go on with the message
    kNewRun,   ///< a later run (or the first message): the join started over; go on
    kStale,    ///< an earlier run's message: drop it
};

/// The join's settings: the struct generated from fusion.proto's fields marked
/// (params_struct) = "JoinParams" (detection_deadline_ms 60, reuse_max_age_ms 100,
/// max_pending 30: defaults, units and ranges are declared there, once).
using JoinConfig = params::fusion::JoinParams;

/// "" when every field is within its declared range, else the first offence.
std::string validate(const JoinConfig& config);

/// What to publish for one frame.
struct JoinDecision {
    uint64_t seq = 0;
    uint64_t epoch = 0;               ///< the run the frame belongs to
    Arrival segments = Arrival::kOk;  ///< the frame's segments status
    bool detections_used = false;     ///< false: published without detections
    uint64_t detections_seq = 0;      ///< which frame's detections (== seq when its own)
    std::string why;                  ///< "own", "deadline, reused N", "deadline", ...
};

class FrameJoin {
  public:
    explicit FrameJoin(JoinConfig config = {});

    /// The run epoch of the next message. kNewRun: the frames of the old run still waiting are
    /// appended to `released` (decided as if their deadline had passed) before the join starts
    /// over; the caller publishes them, then forgets the old run's payloads.
    EpochCheck on_epoch(uint64_t epoch, int64_t now_ns, std::vector<JoinDecision>* released);

    /// The segments of frame `seq`, captured at `capture_ns`, arrived at `now_ns` (local clock).
    void on_segments(uint64_t seq, int64_t capture_ns, Arrival status, int64_t now_ns);
    /// The detections of frame `seq` (captured at `capture_ns`) arrived.
    void on_detections(uint64_t seq, int64_t capture_ns, Arrival status, int64_t now_ns);
    /// Decisions that are due at `now_ns`, in sequence order; each frame is decided once.
    std::vector<JoinDecision> poll(int64_t now_ns);
    /// When poll() should be called next for a deadline (nullopt: nothing waits).
    std::optional<int64_t> next_deadline_ns() const;

    size_t pending() const { return pending_.size(); }
    uint64_t duplicates() const { return duplicates_; }
    /// Messages of an earlier run dropped by on_epoch().
    uint64_t stale() const { return stale_; }
    /// The run being joined (nullopt before the first message).
    std::optional<uint64_t> epoch() const { return epoch_; }

  private:
    struct Pending {
        uint64_t seq;
        int64_t capture_ns;
        int64_t arrived_ns;
        Arrival segments;
    };
    JoinDecision decide(const Pending& p, const char* why);

    JoinConfig config_;
    int64_t deadline_ns_ = 0;                      ///< config_.detection_deadline_ms
    int64_t reuse_ns_ = 0;                         ///< config_.reuse_max_age_ms
    std::deque<Pending> pending_;                  // by seq, ascending
    std::map<uint64_t, Arrival> detections_;       // arrived, frame not yet released
    std::map<uint64_t, int64_t> detection_stamp_;  // capture_ns of those
    std::optional<uint64_t> last_released_;
    std::optional<std::pair<uint64_t, int64_t>> newest_ok_;  // (seq, capture_ns) for reuse
    uint64_t duplicates_ = 0;
    std::optional<uint64_t> epoch_;
    uint64_t stale_ = 0;
};

}  // namespace df::sync
