#include "stage_watch.hpp"

#include <vector>

#include "core/log.hpp"

namespace df::capture {
namespace {

std::vector<dds_instance_handle_t> handles(dds_entity_t endpoint, bool writer) {
    std::vector<dds_instance_handle_t> out(16);
    while (true) {
        const dds_return_t n = writer
                                   ? dds_get_matched_subscriptions(endpoint, out.data(), out.size())
                                   : dds_get_matched_publications(endpoint, out.data(), out.size());
        if (n < 0) return {};
        if (static_cast<size_t>(n) <= out.size()) {
            out.resize(static_cast<size_t>(n));
            return out;
        }
        out.resize(static_cast<size_t>(n));
    }
}

/// The participant of a matched endpoint (0 when it is gone already).
dds_instance_handle_t participant_of(dds_entity_t endpoint, bool writer, dds_instance_handle_t h) {
    dds_builtintopic_endpoint_t* data = writer ? dds_get_matched_subscription_data(endpoint, h)
                                               : dds_get_matched_publication_data(endpoint, h);
    if (data == nullptr) return 0;
    const dds_instance_handle_t p = data->participant_instance_handle;
    dds_builtintopic_free_endpoint(data);
    return p;
}

}  // namespace

StageWatch::StageWatch(std::set<std::string> required, dds_entity_t frames_writer,
                       dds_entity_t acks_reader)
    : required_(std::move(required)),
      frames_writer_(frames_writer),
      acks_reader_(acks_reader),
      waited_(required_) {}

void StageWatch::on_answer(const std::string& stage, dds_instance_handle_t publication) {
    if (required_.count(stage) == 0U) return;
    Known& k = known_[stage];
    k.last_answer_tick = tick_;
    if (k.writer == publication && waited_.count(stage) != 0U) return;
    const dds_instance_handle_t participant = participant_of(acks_reader_, false, publication);
    if (participant != k.participant) k.reads_frames = false;  // learnt again by refresh()
    k.writer = publication;
    k.participant = participant;
    if (waited_.insert(stage).second) {
        log::info("lockstep: stage ", stage, " is back (it answered again); waiting for it");
    }
}

void StageWatch::on_timeout(const std::string& stage) {
    auto it = known_.find(stage);
    if (it == known_.end() || it->second.writer != 0) return;
    rejected_.insert(it->second.participant);
    waited_.erase(stage);
    log::warn("lockstep: the new reader taken for stage ", stage,
              " did not answer; not waiting for it");
}

dds_instance_handle_t StageWatch::candidate(const std::string& stage,
                                            const std::set<dds_instance_handle_t>& readers) const {
    const Known& k = known_.at(stage);
    if (!k.reads_frames) return 0;  // a stage that reads other topics: back when it answers
    for (dds_instance_handle_t p : readers) {
        if (p == k.participant || rejected_.count(p) != 0U) continue;
        if (first_seen_.at(p) <= k.last_answer_tick) continue;  // there before the stage left
        bool claimed = false;
        for (const auto& [other, ko] : known_) claimed = claimed || ko.participant == p;
        if (!claimed) return p;
    }
    return 0;
}

std::set<dds_instance_handle_t> StageWatch::matched_status_writers() const {
    const auto h = handles(acks_reader_, false);
    return {h.begin(), h.end()};
}

std::set<dds_instance_handle_t> StageWatch::frame_reader_participants() const {
    std::set<dds_instance_handle_t> out;
    for (dds_instance_handle_t h : handles(frames_writer_, true)) {
        if (dds_instance_handle_t p = participant_of(frames_writer_, true, h)) out.insert(p);
    }
    return out;
}

void StageWatch::refresh() {
    ++tick_;
    const auto readers = frame_reader_participants();
    for (dds_instance_handle_t p : readers) first_seen_.emplace(p, tick_);
    if (known_.empty()) return;
    const auto writers = matched_status_writers();
    for (auto& [stage, k] : known_) {
        if (waited_.count(stage) == 0U) {
            if (dds_instance_handle_t p = candidate(stage, readers)) {
                k = Known{0, p, k.last_answer_tick, true};
                waited_.insert(stage);
                log::info("lockstep: a new reader of the frames appeared; waiting for stage ",
                          stage, " again");
            }
            continue;
        }
        if (k.participant != 0 && readers.count(k.participant) != 0U) k.reads_frames = true;
        const char* why = nullptr;
        if (k.reads_frames && readers.count(k.participant) == 0U) {
            why = "its reader is gone";
        } else if (k.writer != 0 && writers.count(k.writer) == 0U) {
            why = "its stage_status writer is gone";
        }
        if (why == nullptr) continue;
        waited_.erase(stage);
        log::warn("lockstep: stage ", stage, " left (", why, "); not waiting for it");
    }
}

}  // namespace df::capture
