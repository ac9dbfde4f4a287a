#pragma once
/// A frame joined with the messages other stages publish for it (the SLAM service: the frame
/// with its object segments and geometric segments), by sequence number, as a DDS-free state
/// machine. A frame is ready when every companion stream that has a writer answered it (ok,
/// skipped or failed), or when `deadline_ns` has passed since the frame arrived: a late or
/// missing companion never stalls tracking, it only costs the frame that companion's help.
/// Ready frames come out in sequence order. Runs (header.epoch) are handled by the caller:
/// reset() at a new run.
#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

namespace df::sync {

class CompanionJoin {
  public:
    /// `companions`: how many companion streams; a frame waits at most `deadline_ns`; at most
    /// `max_pending` frames wait (beyond that the oldest is released at once).
    CompanionJoin(int companions, int64_t deadline_ns, size_t max_pending);

    /// Whether companion `which` has a writer now: a stream without one is not waited for.
    void set_expected(int which, bool expected);
    void on_frame(uint64_t seq, int64_t now_ns);
    /// Companion `which` answered frame `seq` (ok: it carries a payload).
    void on_companion(int which, uint64_t seq, bool ok);

    struct Ready {
        uint64_t seq = 0;
        std::vector<bool> ok;  ///< per companion: its payload arrived, ok
        bool late = false;     ///< released by the deadline (or max_pending) with one missing
    };
    /// Frames ready at `now_ns`, in sequence order; each once.
    std::vector<Ready> poll(int64_t now_ns);
    void reset();
    size_t pending() const { return frames_.size(); }

  private:
    struct Waiting {
        int64_t arrived_ns = 0;
        std::vector<int> answers;  ///< per companion: 0 none, 1 ok, 2 answered without payload
    };
    Waiting& entry(uint64_t seq);

    int companions_;
    int64_t deadline_ns_;
    size_t max_pending_;
    std::vector<bool> expected_;
    std::map<uint64_t, Waiting> frames_;    ///< frames that arrived, not yet released
    std::map<uint64_t, Waiting> early_;     ///< companions that came before their frame
};

}  // namespace df::sync
