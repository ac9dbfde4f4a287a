#pragma once
/// Frames a stage never received. Over shared memory a reader that falls behind loses the oldest
/// samples of its history (no back-pressure), so a stage can miss frames it would have skipped
/// anyway. Every stage answers every frame: the sequence numbers missing between two frames of
/// one run are found here, and the stage answers them as skipped.
#include <cstdint>
#include <vector>

namespace df::sync {

class SeqGaps {
  public:
    /// A larger jump is not answered frame by frame (a hostile or corrupt sequence number
    /// would make it answer billions): the stream goes on from the new number.
    static constexpr uint64_t kMaxGap = 1024;

    /// The frame (epoch, seq) arrived: returns the sequence numbers of this run between the
    /// last frame seen and this one that never arrived, in order (at most kMaxGap). A new epoch
    /// (a restarted capture), the first frame, or a frame at or before the last one missed
    /// nothing.
    std::vector<uint64_t> arrived(uint64_t epoch, uint64_t seq);
    /// Frames answered as missed so far.
    uint64_t missed() const { return missed_; }

  private:
    bool started_ = false;
    uint64_t epoch_ = 0;
    uint64_t last_ = 0;
    uint64_t missed_ = 0;
};

}  // namespace df::sync
