#include "capture_node.hpp"

#include <chrono>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "io/openni/openni_source.hpp"
#include "io/tum/tum_folder.hpp"
#include "service/service.hpp"

namespace df::capture {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

Result<std::unique_ptr<CaptureNode>> CaptureNode::create(const config::CaptureConfig& config,
                                                         dds::Participant& participant,
                                                         std::unique_ptr<io::FrameSource> source) {
    const std::string& ns = config.dds().ns();
    auto frames = dds::Writer<df_msg_RgbdFrame>::create(participant,
                                                        dds::topic_name(ns, dds::topics::kFrames));
    if (!frames) return frames.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    auto acks = dds::Reader<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!acks) return acks.status();
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(acks->get()));
    auto node = std::unique_ptr<CaptureNode>(
        new CaptureNode(config, std::move(source), std::move(*frames), std::move(*status),
                        std::move(*acks), std::move(*waitset)));
    if (config.color_small_width() > 0) {
        auto small = dds::Writer<df_msg_CompressedImage>::create(
            participant, dds::topic_name(ns, dds::topics::kColorSmall));
        if (!small) return small.status();
        node->small_.emplace(std::move(*small));
    }
    return node;
}

void CaptureNode::publish_small(const io::RgbdImage& image, const df_msg_Header& header) {
    const int width = static_cast<int>(
        std::min<uint32_t>(config_.color_small_width(), static_cast<uint32_t>(image.rgb.cols)));
    const int height = std::max(1, image.rgb.rows * width / std::max(1, image.rgb.cols));
    cv::Mat small, bgr;
    cv::resize(image.rgb, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);  // imencode takes B,G,R
    std::vector<uint8_t> jpeg;
    const std::vector<int> params = {cv::IMWRITE_JPEG_QUALITY,
                                     static_cast<int>(config_.color_small_jpeg_quality())};
    if (!cv::imencode(".jpg", bgr, jpeg, params) || jpeg.size() > df_msg_MAX_RGB_BYTES) {
        log::warn("seq=", header.seq, " color_small: JPEG encoding failed");
        return;
    }
    df_msg_CompressedImage m{};
    m.header = header;
    m.width = static_cast<uint16_t>(width);
    m.height = static_cast<uint16_t>(height);
    m.source_width = static_cast<uint16_t>(image.rgb.cols);
    m.source_height = static_cast<uint16_t>(image.rgb.rows);
    std::snprintf(m.format, sizeof m.format, "jpeg");
    m.data._buffer = jpeg.data();
    m.data._length = static_cast<uint32_t>(jpeg.size());
    m.data._maximum = static_cast<uint32_t>(jpeg.size());
    m.data._release = false;
    if (Status s = small_->write_copy(m); !s)
        log::warn("seq=", header.seq, " color_small: ", s.message());
}

CaptureNode::CaptureNode(const config::CaptureConfig& config,
                         std::unique_ptr<io::FrameSource> source,
                         dds::Writer<df_msg_RgbdFrame> frames,
                         dds::Writer<df_msg_StageStatus> status,
                         dds::Reader<df_msg_StageStatus> acks, dds::WaitSet waitset)
    : config_(config),
      source_(std::move(source)),
      frames_(std::move(frames)),
      status_(std::move(status)),
      acks_(std::move(acks)),
      waitset_(std::move(waitset)) {
    if (config_.playback() == config::CaptureConfig::LOCKSTEP) {
        required_.insert(config_.lockstep_stages().begin(), config_.lockstep_stages().end());
    }
}

Status CaptureNode::wait_for_subscribers() {
    if (required_.empty()) return Status::ok();
    const auto timeout = static_cast<dds_duration_t>(config_.start_wait_s() * 1e9);
    std::string names;
    for (const auto& s : required_) names += (names.empty() ? "" : ", ") + s;
    log::info("lockstep: waiting up to ", config_.start_wait_s(), " s for ", required_.size(),
              " reader(s) of ", frames_.topic(), " (stages: ", names, ")");
    const Status s = dds::wait_for_matches(frames_.get(), true,
                                           static_cast<uint32_t>(required_.size()), timeout);
    if (!s) {
        return Status(StatusCode::kUnavailable, "lockstep: the stages " + names +
                                                    " did not subscribe to " + frames_.topic() +
                                                    ": " + s.message());
    }
    return Status::ok();
}

void CaptureNode::collect_answers() {
    (void)acks_.take(
        [this](const df_msg_StageStatus& s, const dds_sample_info_t&) {
            const std::string stage = dds::get_name(s.stage);
            if (required_.count(stage) != 0U && s.header.seq + 1 >= seq_) {
                answers_[s.header.seq].insert(stage);
            }
        },
        64);
}

void CaptureNode::wait_for_answers(uint64_t seq) {
    const auto deadline =
        Clock::now() + std::chrono::duration<double>(config_.lockstep_timeout_s());
    while (!service::stop_requested()) {
        collect_answers();
        if (answers_[seq].size() >= required_.size()) break;
        if (Clock::now() >= deadline) {
            std::string missing;
            for (const auto& s : required_) {
                if (answers_[seq].count(s) == 0U) missing += (missing.empty() ? "" : ", ") + s;
            }
            log::error("seq=", seq, " lockstep: no answer from stage(s) ", missing, " within ",
                       config_.lockstep_timeout_s(), " s (did a process die?); going on");
            ++stats_.lockstep_timeouts;
            break;
        }
        (void)waitset_.wait(DDS_MSECS(20));
    }
    answers_.erase(answers_.begin(), answers_.upper_bound(seq));
}

void CaptureNode::pace(int64_t sensor_ns) {
    if (config_.playback() != config::CaptureConfig::REALTIME) return;
    if (first_sensor_ns_ < 0) {
        first_sensor_ns_ = sensor_ns;
        start_wall_ns_ = static_cast<int64_t>(dds::wall_ns());
        return;
    }
    const double rate = config_.rate() > 0 ? config_.rate() : 1.0;
    const auto due = start_wall_ns_ + static_cast<int64_t>((sensor_ns - first_sensor_ns_) / rate);
    const int64_t wait = due - static_cast<int64_t>(dds::wall_ns());
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
}

Status CaptureNode::publish(const io::RgbdImage& image, double read_ms) {
    const auto t0 = Clock::now();
    df_msg_Header header{};
    header.capture_ns = dds::wall_ns();
    header.sensor_ns = static_cast<uint64_t>(image.sensor_ns);
    header.seq = seq_;
    header.source_id = config_.source_id();
    header.status = df_msg_FRAME_OK;
    auto loan = frames_.loan();
    if (!loan) return loan.status();
    if (!loan->shared_memory() && frames_.loans_shared_memory()) ++stats_.loan_fallbacks;
    dds::fill_frame(image, header, loan->get());
    DF_RETURN_IF_ERROR(frames_.write(std::move(*loan)));
    if (small_) publish_small(image, header);
    df_msg_StageStatus st{};
    st.header = header;
    dds::set_name(st.stage, "capture");
    st.timing_count = 2;
    dds::set_name(st.timings[0].name, "read");
    st.timings[0].ms = static_cast<float>(read_ms);
    dds::set_name(st.timings[1].name, "publish");
    st.timings[1].ms = static_cast<float>(ms_since(t0));
    return status_.write_copy(st);
}

Result<CaptureStats> CaptureNode::run() {
    DF_RETURN_IF_ERROR(wait_for_subscribers());
    const auto t_start = Clock::now();
    log::info("capture: publishing ", source_->describe(), " on ", frames_.topic(), " (",
              config::CaptureConfig::Playback_Name(config_.playback()), ")");
    uint32_t loop = 0;
    while (!service::stop_requested()) {
        if (config_.max_frames() > 0 && stats_.published >= config_.max_frames()) break;
        const auto t_read = Clock::now();
        io::FrameRead read = source_->next();
        if (read.kind == io::FrameRead::Kind::kBadFrame) {
            ++stats_.bad_frames;
            log::error("bad frame skipped (", stats_.bad_frames, " so far): ", read.error);
            continue;
        }
        if (read.kind == io::FrameRead::Kind::kEnd) {
            ++loop;
            auto* tum = dynamic_cast<io::TumFolderSource*>(source_.get());
            if (tum == nullptr || (config_.loops() != 0 && loop >= config_.loops())) break;
            tum->rewind();
            first_sensor_ns_ = -1;
            continue;
        }
        const double read_ms = ms_since(t_read);
        pace(read.image.sensor_ns);
        const Status s = publish(read.image, read_ms);
        if (!s) {
            log::error("seq=", seq_, " publishing failed: ", s.message());
        } else {
            ++stats_.published;
            log::debug("seq=", seq_, " published (", read.image.rgb_path, ")");
        }
        if (!required_.empty()) wait_for_answers(seq_);
        ++seq_;
    }
    stats_.elapsed_s = std::chrono::duration<double>(Clock::now() - t_start).count();
    std::this_thread::sleep_for(std::chrono::duration<double>(config_.linger_s()));
    return stats_;
}

}  // namespace df::capture
