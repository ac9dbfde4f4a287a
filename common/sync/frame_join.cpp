#include "sync/frame_join.hpp"

#include <algorithm>

namespace df::sync {

std::string validate(const JoinConfig& c) { return params::check(c); }

FrameJoin::FrameJoin(JoinConfig config)
    : config_(config),
      deadline_ns_(static_cast<int64_t>(config.detection_deadline_ms * 1e6)),
      reuse_ns_(static_cast<int64_t>(config.reuse_max_age_ms * 1e6)) {}

EpochCheck FrameJoin::on_epoch(uint64_t epoch, int64_t now_ns,
                               std::vector<JoinDecision>* released) {
    (void)now_ns;
    if (epoch_ && epoch == *epoch_) return EpochCheck::kCurrent;
    if (epoch_ && epoch < *epoch_) {
        ++stale_;
        return EpochCheck::kStale;
    }
    while (!pending_.empty()) {
        const Pending head = pending_.front();
        pending_.pop_front();
        const auto own = detections_.find(head.seq);
        const char* why = head.segments != Arrival::kOk ? "segments not ok"
                          : own != detections_.end()    ? "own detections"
                                                        : "a new capture run began";
        if (released != nullptr) released->push_back(decide(head, why));
    }
    detections_.clear();
    detection_stamp_.clear();
    last_released_.reset();
    newest_ok_.reset();  // boxes of the old run are not reused for the new one
    epoch_ = epoch;
    return EpochCheck::kNewRun;
}

void FrameJoin::on_segments(uint64_t seq, int64_t capture_ns, Arrival status, int64_t now_ns) {
    if (last_released_ && seq <= *last_released_) {
        ++duplicates_;  // a repeat, or so late that its frame was given up
        return;
    }
    const auto it = std::lower_bound(pending_.begin(), pending_.end(), seq,
                                     [](const Pending& p, uint64_t s) { return p.seq < s; });
    if (it != pending_.end() && it->seq == seq) {
        ++duplicates_;
        return;
    }
    pending_.insert(it, Pending{seq, capture_ns, now_ns, status});
}

void FrameJoin::on_detections(uint64_t seq, int64_t capture_ns, Arrival status, int64_t now_ns) {
    (void)now_ns;
    if (status == Arrival::kOk && (!newest_ok_ || seq > newest_ok_->first)) {
        newest_ok_ = std::make_pair(seq, capture_ns);  // late ones still count for reuse
    }
    if (last_released_ && seq <= *last_released_) return;
    if (detections_.count(seq) != 0) {
        ++duplicates_;
        return;
    }
    detections_[seq] = status;
    detection_stamp_[seq] = capture_ns;
}

JoinDecision FrameJoin::decide(const Pending& p, const char* why) {
    JoinDecision d;
    d.seq = p.seq;
    d.epoch = epoch_.value_or(0);
    d.segments = p.segments;
    d.why = why;
    const auto own = detections_.find(p.seq);
    if (p.segments == Arrival::kOk && own != detections_.end() && own->second == Arrival::kOk) {
        d.detections_used = true;
        d.detections_seq = p.seq;
    } else if (p.segments == Arrival::kOk && newest_ok_ && newest_ok_->first < p.seq &&
               p.capture_ns - newest_ok_->second <= reuse_ns_) {
        d.detections_used = true;
        d.detections_seq = newest_ok_->first;
        d.why += ", reused detections of frame " + std::to_string(newest_ok_->first);
    }
    // Forget everything up to this frame.
    detections_.erase(detections_.begin(), detections_.upper_bound(p.seq));
    detection_stamp_.erase(detection_stamp_.begin(), detection_stamp_.upper_bound(p.seq));
    last_released_ = p.seq;
    return d;
}

std::vector<JoinDecision> FrameJoin::poll(int64_t now_ns) {
    std::vector<JoinDecision> out;
    while (!pending_.empty()) {
        const Pending head = pending_.front();
        const auto own = detections_.find(head.seq);
        const char* why = nullptr;
        if (head.segments != Arrival::kOk) {
            why = "segments not ok";
        } else if (own != detections_.end()) {
            why = own->second == Arrival::kOk ? "own detections" : "detector skipped the frame";
        } else if (now_ns - head.arrived_ns >= deadline_ns_) {
            why = "deadline";
        } else if (pending_.size() > config_.max_pending) {
            why = "too many frames waiting";
        }
        if (why == nullptr) break;
        pending_.pop_front();
        out.push_back(decide(head, why));
    }
    return out;
}

std::optional<int64_t> FrameJoin::next_deadline_ns() const {
    if (pending_.empty()) return std::nullopt;
    return pending_.front().arrived_ns + deadline_ns_;
}

}  // namespace df::sync
