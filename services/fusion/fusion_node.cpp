#include "fusion_node.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>

#include "config/apply_params.hpp"
#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "detect/detector.hpp"
#include "service/service.hpp"

namespace df::fusion_service {
namespace {

int64_t now_ns() { return service::steady_ns(); }

sync::Arrival arrival_of(df_msg_FrameStatus s) {
    switch (s) {
        case df_msg_FRAME_OK:
            return sync::Arrival::kOk;
        case df_msg_FRAME_SKIPPED:
            return sync::Arrival::kSkipped;
        default:
            return sync::Arrival::kFailed;
    }
}

}  // namespace

Result<FusionSettings> settings_from(const config::FusionServiceConfig& c) {
    FusionSettings s;
    DF_RETURN_IF_ERROR(config::apply_params(c, &s.join));
    DF_RETURN_IF_ERROR(config::apply_params(c.instances(), &s.instance));
    DF_RETURN_IF_ERROR(config::apply_params(c.classes(), &s.classes).with_context("classes"));
    DF_RETURN_IF_ERROR(detect::check_class_names(s.classes).with_context("classes"));
    if (std::string e = sync::validate(s.join); !e.empty()) {
        return error(StatusCode::kInvalidArgument, e);
    }
    if (std::string e = seg::validate(s.instance); !e.empty()) {
        return error(StatusCode::kInvalidArgument, e);
    }
    return s;
}

Result<std::unique_ptr<FusionNode>> FusionNode::create(const config::FusionServiceConfig& config,
                                                       const FusionSettings& settings,
                                                       dds::Participant& participant) {
    const std::string& ns = config.dds().ns();
    auto segments = dds::Reader<df_msg_GeometricSegments>::create(
        participant, dds::topic_name(ns, dds::topics::kGeometricSegments));
    if (!segments) return segments.status();
    auto detections = dds::Reader<df_msg_Detections>::create(
        participant, dds::topic_name(ns, dds::topics::kDetections));
    if (!detections) return detections.status();
    auto objects = dds::Writer<df_msg_ObjectSegments>::create(
        participant, dds::topic_name(ns, dds::topics::kObjectSegments));
    if (!objects) return objects.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(segments->get()));
    DF_RETURN_IF_ERROR(waitset->attach_reader(detections->get()));
    return std::unique_ptr<FusionNode>(new FusionNode(config, settings, std::move(*segments),
                                                      std::move(*detections), std::move(*objects),
                                                      std::move(*status), std::move(*waitset)));
}

FusionNode::FusionNode(const config::FusionServiceConfig& config, const FusionSettings& settings,
                       dds::Reader<df_msg_GeometricSegments> segments,
                       dds::Reader<df_msg_Detections> detections,
                       dds::Writer<df_msg_ObjectSegments> objects,
                       dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset)
    : config_(config),
      settings_(settings),
      segments_in_(std::move(segments)),
      detections_in_(std::move(detections)),
      objects_(std::move(objects)),
      status_(std::move(status)),
      waitset_(std::move(waitset)),
      join_(settings.join) {}

bool FusionNode::admit(const df_msg_Header& header, int64_t now) {
    // An epoch is a capture's start; one far in the future (a hostile or broken writer) would
    // make every real run's messages stale.
    constexpr uint64_t kFutureSlackNs = 3'600'000'000'000;  // clocks of two hosts may differ
    if (header.epoch > dds::wall_ns() + kFutureSlackNs) {
        if (future_epochs_++ % 100 == 0) {
            log::warn("seq=", header.seq, " dropped: run epoch ", header.epoch,
                      " ns lies more than an hour in the future (", future_epochs_, " so far)");
        }
        return false;
    }
    std::vector<sync::JoinDecision> released;
    const sync::EpochCheck e = join_.on_epoch(header.epoch, now, &released);
    if (e == sync::EpochCheck::kStale) {
        log::debug("seq=", header.seq, " dropped: a message of an earlier capture run (epoch ",
                   header.epoch, ")");
        return false;
    }
    if (e == sync::EpochCheck::kNewRun) {
        for (const sync::JoinDecision& d : released) publish(d);
        segments_.clear();
        detections_.clear();
        published_without_.clear();
        log::info("seq=", header.seq, " capture run epoch ", header.epoch, ": joining a new run (",
                  released.size(), " frame(s) of the old run released)");
    }
    return true;
}

Status FusionNode::take(int64_t now) {
    auto s = segments_in_.take(
        [&](const df_msg_GeometricSegments& m, const dds_sample_info_t& info) {
            if (!info.valid_data || !admit(m.header, now)) return;
            // Segments this reader lost (it fell behind): those frames are answered skipped.
            for (uint64_t seq : segment_gaps_.arrived(m.header.epoch, m.header.seq)) {
                Segments lost;
                lost.header = m.header;
                lost.header.seq = seq;
                lost.header.status = df_msg_FRAME_SKIPPED;
                segments_[seq] = std::move(lost);
                join_.on_segments(seq, static_cast<int64_t>(m.header.capture_ns),
                                  sync::Arrival::kSkipped, now);
            }
            Segments seg;
            seg.header = m.header;
            const auto checked =
                dds::accept(m, segments_in_.get(), segments_in_.topic(), info, rejects_);
            if (!checked) seg.header.status = df_msg_FRAME_FAILED;
            if (checked && m.header.status == df_msg_FRAME_OK) {
                seg.labels = dds::labels_of(*checked);
                seg.count = static_cast<int>(m.segment_count);
            }
            const auto arrival = !checked ? sync::Arrival::kFailed
                                 : seg.labels.empty() && m.header.status == df_msg_FRAME_OK
                                     ? sync::Arrival::kFailed
                                     : arrival_of(m.header.status);
            segments_[m.header.seq] = std::move(seg);
            join_.on_segments(m.header.seq, static_cast<int64_t>(m.header.capture_ns), arrival,
                              now);
        },
        32);
    if (!s) return s.status();
    const auto& names = detect::coco_names();
    auto d = detections_in_.take(
        [&](const df_msg_Detections& m, const dds_sample_info_t& info) {
            if (!info.valid_data || !admit(m.header, now)) return;
            std::vector<detect::Detection> boxes;
            const bool valid =
                dds::accept(m, detections_in_.get(), detections_in_.topic(), info, rejects_)
                    .is_ok();
            for (uint32_t i = 0; valid && i < m.count; ++i) {
                const df_msg_Detection& b = m.boxes[i];
                detect::Detection det;
                det.box = cv::Rect2f(b.x, b.y, b.w, b.h);
                det.class_id = b.class_id;
                det.class_name = b.class_id >= 0 && static_cast<size_t>(b.class_id) < names.size()
                                     ? names[static_cast<size_t>(b.class_id)]
                                     : "unknown";
                det.score = b.score;
                boxes.push_back(det);
            }
            detections_[m.header.seq] = std::move(boxes);
            join_.on_detections(m.header.seq, static_cast<int64_t>(m.header.capture_ns),
                                valid ? arrival_of(m.header.status) : sync::Arrival::kFailed, now);
            if (valid && m.header.status == df_msg_FRAME_OK && config_.republish_late_ms() > 0)
                republish(m.header.seq);
        },
        32);
    return d ? Status::ok() : d.status();
}

void FusionNode::publish(const sync::JoinDecision& d) {
    const auto it = segments_.find(d.seq);
    if (it == segments_.end()) return;
    const Segments& seg = it->second;
    const std::vector<detect::Detection>* boxes = nullptr;
    if (d.detections_used) {
        const auto det = detections_.find(d.detections_seq);
        if (det != detections_.end()) boxes = &det->second;
    }
    write(seg, d.segments, boxes, d.seq, d.detections_seq, d.why);
    if (config_.republish_late_ms() > 0 && d.segments == sync::Arrival::kOk &&
        !seg.labels.empty() && (boxes == nullptr || d.detections_seq != d.seq)) {
        published_without_[d.seq] = seg;
        // Bounded: at most 32 frames (labels of 640x480: 1.2 MB each).
        while (published_without_.size() > 32) published_without_.erase(published_without_.begin());
    }
    // Payloads up to this frame are done; detections stay a little for reuse.
    segments_.erase(segments_.begin(), segments_.upper_bound(d.seq));
    while (!detections_.empty() && detections_.begin()->first + 16 < d.seq) {
        detections_.erase(detections_.begin());
    }
}

void FusionNode::republish(uint64_t seq) {
    // Forget the frames captured longer ago than republish_late_ms (capture_ns is wall time).
    const int64_t keep_ns = static_cast<int64_t>(config_.republish_late_ms() * 1e6);
    const int64_t now = static_cast<int64_t>(dds::wall_ns());
    for (auto it = published_without_.begin(); it != published_without_.end();) {
        if (now - static_cast<int64_t>(it->second.header.capture_ns) > keep_ns)
            it = published_without_.erase(it);
        else
            ++it;
    }
    const auto it = published_without_.find(seq);
    const auto det = detections_.find(seq);
    if (it == published_without_.end() || det == detections_.end()) return;
    write(it->second, sync::Arrival::kOk, &det->second, seq, seq, "its own detections, late",
          /*late=*/true);
    ++republished_;
    published_without_.erase(it);
}

void FusionNode::write(const Segments& seg, sync::Arrival segments_arrival,
                       const std::vector<detect::Detection>* detections, uint64_t seq,
                       uint64_t detections_seq, const std::string& why, bool late) {
    const auto t0 = now_ns();
    auto loan = objects_.loan();
    if (!loan) {
        log::error("seq=", seq, " no sample to publish: ", loan.status().message());
        return;
    }
    df_msg_ObjectSegments& m = **loan;
    m.header = seg.header;
    m.detections_used = false;
    m.detections_seq = 0;
    m.instance_count = 0;
    // The unused rows too: a loan holds its chunk's old bytes, and every row's enum must be
    // valid for the sample to serialize (UDP to another host, recordings).
    std::memset(m.instances, 0, sizeof(m.instances));
    m.width = m.height = 0;
    if (segments_arrival == sync::Arrival::kOk && !seg.labels.empty()) {
        std::vector<detect::Detection> boxes;
        // Frames since the detector saw these boxes (0: this frame's own detections).
        const auto age = static_cast<uint16_t>(
            detections == nullptr ? 0 : dds::frames_since_detection(seq, detections_seq));
        if (detections != nullptr) {
            boxes = *detections;
            m.detections_used = true;
            m.detections_seq = detections_seq;
        }
        const auto kind_of = [this](const detect::Detection& x) {
            return detect::class_kind(settings_.classes, x.class_name);
        };
        auto r = seg::segment_instances(seg.labels, seg.count, cv::Mat(), boxes, kind_of,
                                        settings_.instance);
        if (!r) {
            log::error("seq=", seq, " ", r.status().message());
            m.header.status = df_msg_FRAME_FAILED;
        } else {
            m.header.status = df_msg_FRAME_OK;
            m.width = static_cast<uint16_t>(seg.labels.cols);
            m.height = static_cast<uint16_t>(seg.labels.rows);
            for (const seg::Instance& inst : r->instances) {
                if (m.instance_count >= df_msg_MAX_INSTANCES) break;
                df_msg_InstanceInfo& info = m.instances[m.instance_count++];
                info.instance_id = static_cast<uint16_t>(inst.id);
                info.class_id = inst.detection.class_id;
                info.score = inst.detection.score;
                info.kind = inst.kind == detect::ClassKind::kNonRigid ? df_msg_OBJECT_NON_RIGID
                                                                      : df_msg_OBJECT_RIGID;
                info.box_x = inst.detection.box.x;
                info.box_y = inst.detection.box.y;
                info.box_w = inst.detection.box.width;
                info.box_h = inst.detection.box.height;
                info.pixel_count = static_cast<uint32_t>(inst.pixels);
                info.age_frames = age;
                ++instances_by_class_[inst.detection.class_name];
            }
            // Persons no segment explained still come with their box (0 pixels), so that SLAM
            // can leave the box's foreground out (docs/dynamics.md).
            int next_id = 1;
            for (const seg::Instance& inst : r->instances) next_id = std::max(next_id, inst.id + 1);
            for (const detect::Detection& b : boxes) {
                if (kind_of(b) != detect::ClassKind::kNonRigid) continue;
                bool segmented = false;
                for (const seg::Instance& inst : r->instances)
                    segmented = segmented || (inst.detection.box == b.box &&
                                              inst.detection.class_id == b.class_id);
                if (segmented || m.instance_count >= df_msg_MAX_INSTANCES || next_id > 65535)
                    continue;
                df_msg_InstanceInfo& info = m.instances[m.instance_count++];
                info.instance_id = static_cast<uint16_t>(next_id++);
                info.class_id = b.class_id;
                info.score = b.score;
                info.kind = df_msg_OBJECT_NON_RIGID;
                info.box_x = b.box.x;
                info.box_y = b.box.y;
                info.box_w = b.box.width;
                info.box_h = b.box.height;
                info.pixel_count = 0;
                info.age_frames = age;
            }
            uint16_t* out = m.labels;
            for (int y = 0; y < r->labels.rows; ++y) {
                const uint16_t* row = r->labels.ptr<uint16_t>(y);
                out = std::copy(row, row + r->labels.cols, out);
            }
        }
    } else {
        m.header.status = segments_arrival == sync::Arrival::kSkipped ? df_msg_FRAME_SKIPPED
                                                                      : df_msg_FRAME_FAILED;
    }
    const uint32_t instances = m.instance_count;
    const bool used = m.detections_used;
    const df_msg_Header header = m.header;
    if (Status s = objects_.write(std::move(*loan)); !s) log::warn("seq=", seq, " ", s.message());
    if (!late) {
        ++published_;
        if (!used) {
            ++without_;
        } else if (detections_seq == seq) {
            ++with_own_;
        } else {
            ++with_reused_;
        }
    }
    log::debug("seq=", seq, " ", instances, " instances (", why, ")");
    df_msg_StageStatus st{};
    st.header = header;
    dds::set_name(st.stage, config_.stage());
    st.timing_count = 1;
    dds::set_name(st.timings[0].name, "fuse");
    st.timings[0].ms = static_cast<float>(static_cast<double>(now_ns() - t0) * 1e-6);
    (void)status_.write_copy(st);
}

Status FusionNode::run() {
    log::info("joining ", segments_in_.topic(), " and ", detections_in_.topic(), " (deadline ",
              config_.detection_deadline_ms(), " ms)");
    service::StreamEnd stream(config_.idle_exit_s(), config_.writers_grace_s());
    while (!service::stop_requested()) {
        const int64_t now = now_ns();
        int64_t wait_ns = 100'000'000;
        if (auto next = join_.next_deadline_ns())
            wait_ns = std::clamp<int64_t>(*next - now, 0, wait_ns);
        auto woke = waitset_.wait(wait_ns);
        if (!woke) return woke.status();
        DF_RETURN_IF_ERROR(take(now_ns()));
        // With no detector on the topic there is nothing to wait for: release at once (as if
        // the deadline had passed) instead of delaying every frame by it.
        const int64_t poll_at =
            detections_in_.matched_writers() == 0
                ? now_ns() + static_cast<int64_t>(settings_.join.detection_deadline_ms * 1e6)
                : now_ns();
        for (const sync::JoinDecision& d : join_.poll(poll_at)) {
            stream.on_input();
            publish(d);
        }
        if (const char* why = stream.check(segments_in_.matched_writers(), join_.pending() == 0)) {
            std::string classes;
            for (const auto& [name, n] : instances_by_class_) {
                classes += (classes.empty() ? "" : ", ") + name + " " + std::to_string(n);
            }
            log::info("stream ended (", why, "): ", published_, " frames published (", with_own_,
                      " with their own detections, ", with_reused_, " with reused ones, ", without_,
                      " without; ", republished_, " of them published again with their own, late)",
                      "; instances: ", classes.empty() ? "none" : classes);
            if (config_.exit_at_end()) return Status::ok();
            stream.reset();
            published_ = with_own_ = with_reused_ = without_ = republished_ = 0;
            published_without_.clear();
            instances_by_class_.clear();
        }
    }
    return Status::ok();
}

}  // namespace df::fusion_service
