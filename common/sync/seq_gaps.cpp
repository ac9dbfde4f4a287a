#include "sync/seq_gaps.hpp"

namespace df::sync {

std::vector<uint64_t> SeqGaps::arrived(uint64_t epoch, uint64_t seq) {
    std::vector<uint64_t> gap;
    if (started_ && epoch == epoch_ && seq > last_ + 1 && seq - last_ - 1 <= kMaxGap) {
        for (uint64_t s = last_ + 1; s < seq; ++s) gap.push_back(s);
        missed_ += gap.size();
    }
    if (!started_ || epoch != epoch_ || seq > last_) last_ = seq;
    started_ = true;
    epoch_ = epoch;
    return gap;
}

}  // namespace df::sync
