#include "detector_node.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "eval/segmentation.hpp"
#include "service/service.hpp"

namespace df::detector_service {
namespace {

int64_t now_ns() { return service::steady_ns(); }

}  // namespace

Result<std::unique_ptr<DetectorNode>> DetectorNode::create(
    const config::DetectorServiceConfig& config, std::unique_ptr<BoxSource> source,
    dds::Participant& participant) {
    const std::string& ns = config.dds().ns();
    if (config.input() != "frames" && config.input() != "color_small") {
        return error(StatusCode::kInvalidArgument,
                     "input must be \"frames\" or \"color_small\", got \"" + config.input() + "\"");
    }
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    std::optional<dds::Reader<df_msg_RgbdFrame>> frames;
    std::optional<dds::Reader<df_msg_CompressedImage>> small;
    if (config.input() == "frames") {
        auto r = dds::Reader<df_msg_RgbdFrame>::create(participant,
                                                       dds::topic_name(ns, dds::topics::kFrames));
        if (!r) return r.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(r->get()));
        frames.emplace(std::move(*r));
    } else {
        auto r = dds::Reader<df_msg_CompressedImage>::create(
            participant, dds::topic_name(ns, dds::topics::kColorSmall));
        if (!r) return r.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(r->get()));
        small.emplace(std::move(*r));
    }
    auto detections = dds::Writer<df_msg_Detections>::create(
        participant, dds::topic_name(ns, dds::topics::kDetections));
    if (!detections) return detections.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    return std::unique_ptr<DetectorNode>(
        new DetectorNode(config, std::move(source), std::move(frames), std::move(small),
                         std::move(*detections), std::move(*status), std::move(*waitset)));
}

DetectorNode::DetectorNode(const config::DetectorServiceConfig& config,
                           std::unique_ptr<BoxSource> source,
                           std::optional<dds::Reader<df_msg_RgbdFrame>> frames,
                           std::optional<dds::Reader<df_msg_CompressedImage>> small,
                           dds::Writer<df_msg_Detections> detections,
                           dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset)
    : config_(config),
      source_(std::move(source)),
      frames_(std::move(frames)),
      small_(std::move(small)),
      detections_(std::move(detections)),
      status_(std::move(status)),
      waitset_(std::move(waitset)) {}

void DetectorNode::answer(const df_msg_Header& header, df_msg_FrameStatus status,
                          const std::vector<detect::Detection>& boxes, int width, int height,
                          double ms) {
    df_msg_Detections m{};
    m.header = header;
    m.header.status = status;
    m.image_width = static_cast<uint16_t>(width);
    m.image_height = static_cast<uint16_t>(height);
    for (const detect::Detection& d : boxes) {
        if (m.count >= df_msg_MAX_DETECTIONS) break;
        df_msg_Detection& b = m.boxes[m.count++];
        b.x = d.box.x;
        b.y = d.box.y;
        b.w = d.box.width;
        b.h = d.box.height;
        b.class_id = d.class_id;
        b.score = d.score;
    }
    if (Status s = detections_.write_copy(m); !s) log::warn("seq=", header.seq, " ", s.message());
    df_msg_StageStatus st{};
    st.header = m.header;
    dds::set_name(st.stage, config_.stage());
    if (status == df_msg_FRAME_OK) {
        st.timing_count = 1;
        dds::set_name(st.timings[0].name, "detect");
        st.timings[0].ms = static_cast<float>(ms);
    }
    (void)status_.write_copy(st);
}

void DetectorNode::answer_missed(const Pending& p) {
    const std::vector<uint64_t> missed = gaps_.arrived(p.header.epoch, p.header.seq);
    if (missed.empty()) return;
    log::info("seq=", p.header.seq, " frames ", missed.front(), "..", missed.back(),
              " never reached this stage (the reader fell behind): answered skipped");
    df_msg_Header h = p.header;
    for (uint64_t seq : missed) {
        h.seq = seq;
        ++skipped_;
        answer(h, df_msg_FRAME_SKIPPED, {}, p.source_width, p.source_height, 0);
    }
}

void DetectorNode::handle(const Pending& p) {
    const df_msg_Header& header = p.header;
    const uint32_t nth = std::max<uint32_t>(1, config_.every_nth());
    if (header.seq % nth != 0) {
        ++skipped_;
        answer(header, df_msg_FRAME_SKIPPED, {}, p.source_width, p.source_height, 0);
        return;
    }
    if (p.image.rgb.empty()) {
        ++failed_;
        log::error("seq=", header.seq, " undecodable colour image");
        answer(header, df_msg_FRAME_FAILED, {}, p.source_width, p.source_height, 0);
        return;
    }
    const int64_t t0 = now_ns();
    auto boxes = source_->detect(p.image, header.seq);
    const double ms = static_cast<double>(now_ns() - t0) * 1e-6;
    if (!boxes) {
        ++failed_;
        log::error("seq=", header.seq, " ", boxes.status().message());
        answer(header, df_msg_FRAME_FAILED, {}, p.source_width, p.source_height, ms);
        return;
    }
    // Back to the pixels of the full frame.
    const float sx = static_cast<float>(p.source_width) / static_cast<float>(p.image.rgb.cols);
    const float sy = static_cast<float>(p.source_height) / static_cast<float>(p.image.rgb.rows);
    for (detect::Detection& d : *boxes) {
        d.box = cv::Rect2f(d.box.x * sx, d.box.y * sy, d.box.width * sx, d.box.height * sy);
    }
    ++detected_;
    answer(header, df_msg_FRAME_OK, *boxes, p.source_width, p.source_height, ms);
}

Status DetectorNode::take(std::vector<Pending>* pending) {
    if (frames_) {
        auto taken = frames_->take_batch(
            [&](const df_msg_RgbdFrame& f, const dds_sample_info_t& info, bool newest) {
                if (!info.valid_data) return;
                auto frame = dds::accept(f, frames_->get(), frames_->topic(), info, rejects_);
                if (!frame) {
                    pending->push_back({{}, f.header, 0, 0, false});
                    return;
                }
                // Only the newest is detected (the older ones are answered skipped): only it
                // is copied out of the loan.
                Pending p{newest ? dds::to_image(*frame) : io::RgbdImage{}, f.header, f.width,
                          f.height};
                pending->push_back(std::move(p));
            },
            16);
        return taken ? Status::ok() : taken.status();
    }
    auto taken = small_->take(
        [&](const df_msg_CompressedImage& m, const dds_sample_info_t& info) {
            if (!info.valid_data) return;
            Pending p;
            p.header = m.header;
            if (!dds::accept(m, small_->get(), small_->topic(), info, rejects_)) {
                p.valid = false;
                pending->push_back(std::move(p));
                return;
            }
            p.source_width = m.source_width;
            p.source_height = m.source_height;
            p.image.sensor_ns = static_cast<int64_t>(m.header.sensor_ns);
            // A checked sample's encoded header says width x height; the decoder may still
            // refuse corrupt data (an empty image, or an exception): answered as failed.
            try {
                if (m.data._length > 0) {
                    const cv::Mat bytes(1, static_cast<int>(m.data._length), CV_8UC1,
                                        m.data._buffer);
                    const cv::Mat bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
                    if (!bgr.empty() && bgr.cols == m.width && bgr.rows == m.height)
                        cv::cvtColor(bgr, p.image.rgb, cv::COLOR_BGR2RGB);
                }
            } catch (const cv::Exception& e) {
                log::warn("seq=", m.header.seq, " colour image not decoded: ", e.what());
            }
            pending->push_back(std::move(p));
        },
        16);
    return taken ? Status::ok() : taken.status();
}

uint32_t DetectorNode::matched_writers() const {
    return frames_ ? frames_->matched_writers() : small_->matched_writers();
}

Status DetectorNode::run() {
    log::info(source_->describe(), "; waiting for frames on ",
              frames_ ? frames_->topic() : small_->topic());
    service::StreamEnd stream(config_.idle_exit_s(), config_.writers_grace_s());
    while (!service::stop_requested()) {
        auto woke = waitset_.wait(DDS_MSECS(100));
        if (!woke) return woke.status();
        std::vector<Pending> pending;
        DF_RETURN_IF_ERROR(take(&pending));
        for (size_t i = 0; i < pending.size(); ++i) {
            stream.on_input();
            if (!pending[i].valid) {
                ++failed_;
                answer(pending[i].header, df_msg_FRAME_FAILED, {}, 0, 0, 0);
                continue;
            }
            answer_missed(pending[i]);
            if (i + 1 < pending.size()) {  // stay current: answer the older ones skipped
                ++skipped_;
                answer(pending[i].header, df_msg_FRAME_SKIPPED, {}, pending[i].source_width,
                       pending[i].source_height, 0);
            } else {
                handle(pending[i]);
            }
        }
        if (const char* why = stream.check(matched_writers(), pending.empty())) {
            log::info("stream ended (", why, "): ", detected_, " frames detected, ", skipped_,
                      " skipped, ", failed_, " failed (",
                      gaps_.missed(), " of the skipped never reached the reader)");
            if (config_.exit_at_end()) return Status::ok();
            stream.reset();
            gaps_ = {};
            detected_ = skipped_ = failed_ = 0;
        }
    }
    return Status::ok();
}

}  // namespace df::detector_service
