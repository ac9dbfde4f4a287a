#include "sync/companion_join.hpp"

namespace df::sync {

CompanionJoin::CompanionJoin(int companions, int64_t deadline_ns, size_t max_pending)
    : companions_(companions),
      deadline_ns_(deadline_ns),
      max_pending_(max_pending < 1 ? 1 : max_pending),
      expected_(static_cast<size_t>(companions), true) {}

void CompanionJoin::set_expected(int which, bool expected) {
    if (which >= 0 && which < companions_) expected_[static_cast<size_t>(which)] = expected;
}

CompanionJoin::Waiting& CompanionJoin::entry(uint64_t seq) {
    Waiting& w = frames_[seq];
    if (w.answers.empty()) w.answers.assign(static_cast<size_t>(companions_), 0);
    return w;
}

void CompanionJoin::on_frame(uint64_t seq, int64_t now_ns) {
    if (frames_.count(seq) != 0U) return;  // a duplicate
    Waiting& w = entry(seq);
    w.arrived_ns = now_ns;
    const auto early = early_.find(seq);
    if (early != early_.end()) {
        w.answers = early->second.answers;
        early_.erase(early);
    }
}

void CompanionJoin::on_companion(int which, uint64_t seq, bool ok) {
    if (which < 0 || which >= companions_) return;
    auto it = frames_.find(seq);
    Waiting* w = nullptr;
    if (it != frames_.end()) {
        w = &it->second;
    } else {
        // Its frame has not come yet (or was released already: then this is stale and the
        // early entry is dropped with the older ones below).
        Waiting& e = early_[seq];
        if (e.answers.empty()) e.answers.assign(static_cast<size_t>(companions_), 0);
        w = &e;
        while (early_.size() > 4 * max_pending_) early_.erase(early_.begin());
    }
    w->answers[static_cast<size_t>(which)] = ok ? 1 : 2;
}

std::vector<CompanionJoin::Ready> CompanionJoin::poll(int64_t now_ns) {
    std::vector<Ready> out;
    while (!frames_.empty()) {
        auto it = frames_.begin();
        const Waiting& w = it->second;
        bool complete = true;
        for (int c = 0; c < companions_; ++c)
            if (expected_[static_cast<size_t>(c)] && w.answers[static_cast<size_t>(c)] == 0)
                complete = false;
        const bool due = now_ns - w.arrived_ns >= deadline_ns_;
        const bool overflow = frames_.size() > max_pending_;
        if (!complete && !due && !overflow) break;
        Ready r;
        r.seq = it->first;
        r.late = !complete;
        for (int c = 0; c < companions_; ++c) r.ok.push_back(w.answers[static_cast<size_t>(c)] == 1);
        out.push_back(r);
        frames_.erase(it);
        // Companions of frames older than the one released will never be used.
        early_.erase(early_.begin(), early_.lower_bound(r.seq + 1));
    }
    return out;
}

void CompanionJoin::reset() {
    frames_.clear();
    early_.clear();
}

}  // namespace df::sync
