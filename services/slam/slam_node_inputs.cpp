// SlamNode's input side: frames, object segments and geometric segments taken from their
// readers into the join (late object segments of frames already tracked go to the system).
#include "dds/msg_convert.hpp"
#include "service/service.hpp"
#include "slam_node.hpp"

namespace df::slam_service {

Status SlamNode::take_inputs(size_t* frames_taken) {
    const int64_t now = service::steady_ns();
    // A message of another capture run than the frames being joined: start the join over.
    const auto epoch_of = [this](const df_msg_Header& h) {
        if (h.epoch == join_epoch_) return true;
        if (h.epoch < join_epoch_) return false;  // an earlier run: stale
        for (auto& [seq, f] : waiting_) answer_unprocessed(f.header, df_msg_FRAME_SKIPPED);
        waiting_.clear();
        objects_in_.clear();
        geometric_in_.clear();
        join_.reset();
        join_epoch_ = h.epoch;
        return true;
    };
    auto taken = frames_.take(
        [&](const df_msg_RgbdFrame& f, const dds_sample_info_t& info) {
            if (!info.valid_data) return;
            auto frame = dds::accept(f, frames_.get(), frames_.topic(), info, rejects_);
            if (!frame) {
                ++failed_;
                answer_unprocessed(f.header, df_msg_FRAME_FAILED);
                return;
            }
            if (!epoch_of(f.header)) return;
            // Frames this reader lost (it fell behind): answered skipped, so no stage waits.
            df_msg_Header lost = f.header;
            for (uint64_t seq : frame_gaps_.arrived(f.header.epoch, f.header.seq)) {
                ++skipped_;
                lost.seq = seq;
                answer_unprocessed(lost, df_msg_FRAME_SKIPPED);
            }
            waiting_[f.header.seq] = {dds::to_image(*frame), f.header};
            join_.on_frame(f.header.seq, now);
            ++*frames_taken;
        },
        16);
    if (!taken) return taken.status();
    if (objects_) {
        join_.set_expected(0, objects_->matched_writers() > 0);
        auto t = objects_->take(
            [&](const df_msg_ObjectSegments& m, const dds_sample_info_t& info) {
                if (!info.valid_data || !epoch_of(m.header)) return;
                auto checked = dds::accept(m, objects_->get(), objects_->topic(), info, rejects_);
                const bool ok = checked && m.header.status == df_msg_FRAME_OK;
                if (!ok) return;
                // Published without detections, or with an earlier frame's (reused boxes).
                const int age = !m.detections_used ? -1
                                                   : dds::frames_since_detection(
                                                         m.header.seq, m.detections_seq);
                if (system_ && have_last_ && m.header.epoch == last_epoch_ &&
                    m.header.seq <= last_seq_ && !waiting_.count(m.header.seq)) {
                    // Its frame was tracked without them (the deadline passed): the detector's
                    // instances are still the newest, carried forward from the next frame on.
                    if (age == 0 &&
                        system_->take_late_instances(static_cast<int64_t>(m.header.sensor_ns),
                                                     dds::to_label_image(*checked)))
                        ++late_instances_taken_;
                    return;
                }
                objects_in_[m.header.seq] = {dds::to_label_image(*checked), age};
                join_.on_companion(0, m.header.seq, ok);
            },
            16);
        if (!t) return t.status();
    } else {
        join_.set_expected(0, false);
    }
    if (geometric_) {
        join_.set_expected(1, geometric_->matched_writers() > 0);
        auto t = geometric_->take(
            [&](const df_msg_GeometricSegments& m, const dds_sample_info_t& info) {
                if (!info.valid_data || !epoch_of(m.header)) return;
                auto checked =
                    dds::accept(m, geometric_->get(), geometric_->topic(), info, rejects_);
                const bool ok = checked && m.header.status == df_msg_FRAME_OK;
                if (ok)
                    geometric_in_[m.header.seq] = {dds::labels_of(*checked),
                                                   static_cast<int>(m.segment_count)};
                join_.on_companion(1, m.header.seq, ok);
            },
            16);
        if (!t) return t.status();
    } else {
        join_.set_expected(1, false);
    }
    // Segments of frames that are gone (released, or never came) are dropped.
    const uint64_t oldest = waiting_.empty() ? UINT64_MAX : waiting_.begin()->first;
    const auto trim = [oldest](auto& m) {
        while (!m.empty() && m.begin()->first < oldest && m.size() > 60) m.erase(m.begin());
    };
    trim(objects_in_);
    trim(geometric_in_);
    return Status::ok();
}

}  // namespace df::slam_service
