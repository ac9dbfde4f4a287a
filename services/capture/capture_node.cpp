#include "capture_node.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
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
    auto guard = FramesGuard::create(participant.get(), frames->get(), frames->topic());
    if (!guard) return guard.status();
    auto node = std::unique_ptr<CaptureNode>(
        new CaptureNode(config, std::move(source), std::move(*frames), std::move(*status),
                        std::move(*acks), std::move(*waitset), std::move(*guard)));
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
                         dds::Reader<df_msg_StageStatus> acks, dds::WaitSet waitset,
                         FramesGuard guard)
    : config_(config),
      source_(std::move(source)),
      frames_(std::move(frames)),
      status_(std::move(status)),
      acks_(std::move(acks)),
      waitset_(std::move(waitset)),
      guard_(std::move(guard)),
      epoch_(dds::wall_ns()),
      created_(Clock::now()) {
    if (config_.playback() == config::CaptureConfig::LOCKSTEP) {
        required_.insert(config_.lockstep_stages().begin(), config_.lockstep_stages().end());
        watch_.emplace(required_, frames_.get(), acks_.get());
    }
}

bool CaptureNode::sleep_unless_stopped(double seconds) {
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(std::max(0.0, seconds)));
    while (!service::stop_requested()) {
        const auto left = until - Clock::now();
        if (left <= Clock::duration::zero()) return true;
        std::this_thread::sleep_for(std::min<Clock::duration>(left, std::chrono::milliseconds(50)));
    }
    return false;
}

Status CaptureNode::check_single_writer(bool wait) {
    // Discovery of a writer already running takes a moment on loopback: look for one until
    // 0.7 s after our writer was created (the wait for subscribers counts towards it).
    const auto until = created_ + std::chrono::milliseconds(700);
    while (!service::stop_requested()) {
        const auto others = guard_.other_writers();
        if (!others.empty()) {
            std::string names;
            for (const auto& o : others) names += (names.empty() ? "" : "; ") + o;
            return Status(StatusCode::kUnavailable,
                          "another writer of " + frames_.topic() + " is running (" + names +
                              "): two captures on one namespace would interleave their frames; "
                              "stop it or give this capture another dds.ns");
        }
        if (!wait || Clock::now() >= until) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return Status::ok();
}

Status CaptureNode::wait_for_subscribers() {
    if (required_.empty()) return Status::ok();
    std::string names;
    for (const auto& s : required_) names += (names.empty() ? "" : ", ") + s;
    log::info("lockstep: waiting up to ", config_.start_wait_s(), " s for ", required_.size(),
              " reader(s) of ", frames_.topic(), " (stages: ", names, ")");
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(config_.start_wait_s()));
    // In 0.1 s slices so that a stop request ends the wait at once.
    while (!service::stop_requested()) {
        DF_RETURN_IF_ERROR(check_single_writer(false));
        const Status s = dds::wait_for_matches(
            frames_.get(), true, static_cast<uint32_t>(required_.size()), DDS_MSECS(100));
        if (s) return Status::ok();
        if (Clock::now() >= deadline) {
            return Status(StatusCode::kUnavailable,
                          "lockstep: the stages " + names + " did not subscribe to " +
                              frames_.topic() + " within " +
                              std::to_string(config_.start_wait_s()) + " s: " + s.message());
        }
    }
    return Status::ok();
}

void CaptureNode::collect_answers() {
    (void)acks_.take(
        [this](const df_msg_StageStatus& sample, const dds_sample_info_t& info) {
            auto checked = dds::accept(sample, acks_.get(), acks_.topic(), info, rejects_);
            if (!checked) {
                ++stats_.bad_answers;
                return;
            }
            const df_msg_StageStatus& s = checked->get();
            const std::string stage = dds::get_name(s.stage);
            // Answers of an earlier run (a capture that was restarted) are not ours.
            if (required_.count(stage) == 0U || s.header.epoch != epoch_) return;
            watch_->on_answer(stage, info.publication_handle);
            if (s.header.seq + 1 >= seq_) answers_[s.header.seq].insert(stage);
        },
        64);
}

void CaptureNode::wait_for_answers(uint64_t seq) {
    const auto deadline =
        Clock::now() + std::chrono::duration<double>(config_.lockstep_timeout_s());
    auto next_refresh = Clock::now();
    const uint64_t departed_before = departed_frame_readers();
    while (!service::stop_requested()) {
        collect_answers();
        if (Clock::now() >= next_refresh) {
            watch_->refresh();
            next_refresh = Clock::now() + std::chrono::milliseconds(100);
            // A stage between us and a lockstep stage (geoseg before fusion) that was killed
            // took this frame with it: its answer never comes, so stop waiting for it.
            if (departed_frame_readers() > departed_before) {
                log::warn("seq=", seq, " lockstep: a reader of the frames left while this ",
                          "frame was out; not waiting for its answers");
                ++stats_.frames_abandoned;
                break;
            }
        }
        const std::set<std::string>& waited = watch_->waited();
        bool all = true;
        for (const auto& s : waited) all = all && answers_[seq].count(s) != 0U;
        if (all) {
            if (waited.size() < required_.size()) ++stats_.stages_left;
            break;
        }
        if (Clock::now() >= deadline) {
            std::string missing;
            for (const auto& s : waited) {
                if (answers_[seq].count(s) == 0U) missing += (missing.empty() ? "" : ", ") + s;
            }
            log::error("seq=", seq, " lockstep: no answer from stage(s) ", missing, " within ",
                       config_.lockstep_timeout_s(), " s (did a process die?); going on");
            for (const auto& s : required_) {
                if (answers_[seq].count(s) == 0U) watch_->on_timeout(s);
            }
            ++stats_.lockstep_timeouts;
            break;
        }
        (void)waitset_.wait(DDS_MSECS(20));
    }
    answers_.erase(answers_.begin(), answers_.upper_bound(seq));
}

uint64_t CaptureNode::departed_frame_readers() const {
    dds_publication_matched_status_t st{};
    if (dds_get_publication_matched_status(frames_.get(), &st) != DDS_RETCODE_OK) return 0;
    return st.total_count >= st.current_count ? st.total_count - st.current_count : 0;
}

bool CaptureNode::pace(int64_t sensor_ns) {
    if (config_.playback() != config::CaptureConfig::REALTIME) return true;
    if (first_sensor_ns_ < 0) {
        first_sensor_ns_ = sensor_ns;
        start_wall_ns_ = static_cast<int64_t>(dds::wall_ns());
        return true;
    }
    const double rate = config_.rate() > 0 ? config_.rate() : 1.0;
    const auto due = start_wall_ns_ + static_cast<int64_t>((sensor_ns - first_sensor_ns_) / rate);
    const int64_t wait = due - static_cast<int64_t>(dds::wall_ns());
    return wait <= 0 || sleep_unless_stopped(static_cast<double>(wait) * 1e-9);
}

Status CaptureNode::publish(const io::RgbdImage& image, double read_ms) {
    const auto t0 = Clock::now();
    df_msg_Header header{};
    header.capture_ns = dds::wall_ns();
    header.sensor_ns = static_cast<uint64_t>(image.sensor_ns);
    header.seq = seq_;
    header.epoch = epoch_;
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

bool CaptureNode::resume() {
    std::error_code ec;
    const std::filesystem::path folder = std::filesystem::weakly_canonical(config_.folder(), ec);
    resume_.folder = ec ? config_.folder() : folder.string();
    resume_.ns = config_.dds().ns();
    resume_.source_id = config_.source_id();
    const std::string& file = config_.resume_file();
    auto* tum = dynamic_cast<io::TumFolderSource*>(source_.get());
    if (tum == nullptr) {
        log::warn("resume_file ", file, " applies to a TUM folder; a live source goes on from now");
        return true;
    }
    auto saved = read_resume_state(file);
    if (!saved) {
        log::warn(saved.status().message(), "; playing from frame 0 and writing it anew");
        return true;
    }
    if (!saved->has_value()) {
        log::info("resume file ", file, ": none yet, playing from frame 0");
        return true;
    }
    const ResumeState& s = **saved;
    if (const std::string why = resume_mismatch(s, resume_); !why.empty()) {
        log::warn("resume file ", file, " ignored (", why, "); playing from frame 0");
        return true;
    }
    resume_ = s;
    if (s.finished) {
        log::info("resume file ", file, ": the previous run played ", resume_.folder,
                  " to its end (", s.frames_done, " frames); nothing left to publish (remove ",
                  "the file to play it again)");
        stats_.nothing_left = true;
        return false;
    }
    const auto& pairs = tum->pairs();
    size_t index = 0;
    while (index < pairs.size() && pairs[index].rgb.stamp_ns <= s.last_sensor_ns) ++index;
    tum->seek(index);
    loop_ = s.loop;
    stats_.resumed = true;
    log::info("resume file ", file, ": going on after the frame stamped ", s.last_sensor_ns,
              " ns (loop ", s.loop, ", ", s.frames_done, " frames done before): frame ", index,
              " of ", pairs.size(), " is next");
    return true;
}

void CaptureNode::record_done(int64_t sensor_ns, bool finished) {
    if (config_.resume_file().empty()) return;
    if (sensor_ns >= 0) {
        resume_.last_sensor_ns = sensor_ns;
        resume_.loop = loop_;
        ++resume_.frames_done;
    }
    resume_.finished = finished;
    if (Status s = write_resume_state(config_.resume_file(), resume_); !s) {
        log::warn("seq=", seq_, " ", s.message());
    }
}

Result<CaptureStats> CaptureNode::run() {
    DF_RETURN_IF_ERROR(check_single_writer(false));
    if (!config_.resume_file().empty() && !resume()) {
        (void)sleep_unless_stopped(config_.linger_s());
        return stats_;
    }
    const uint64_t done_before = resume_.frames_done;
    // The two waits overlap: a restarted capture whose readers are there goes on 0.7 s after
    // its start, not 0.7 s plus the shared-memory settle.
    DF_RETURN_IF_ERROR(wait_for_subscribers());
    DF_RETURN_IF_ERROR(check_single_writer(true));
    const auto t_start = Clock::now();
    log::info("capture: publishing ", source_->describe(), " on ", frames_.topic(), " (",
              config::CaptureConfig::Playback_Name(config_.playback()), ", run epoch ", epoch_,
              ")");
    bool played_out = false;  // the source's end (or max_frames), not a stop request
    while (!service::stop_requested()) {
        if (config_.max_frames() > 0 && done_before + stats_.published >= config_.max_frames()) {
            played_out = true;
            break;
        }
        const auto t_read = Clock::now();
        io::FrameRead read = source_->next();
        if (read.kind == io::FrameRead::Kind::kBadFrame) {
            ++stats_.bad_frames;
            log::error("bad frame skipped (", stats_.bad_frames, " so far): ", read.error);
            continue;
        }
        if (read.kind == io::FrameRead::Kind::kEnd) {
            ++loop_;
            auto* tum = dynamic_cast<io::TumFolderSource*>(source_.get());
            if (tum == nullptr || (config_.loops() != 0 && loop_ >= config_.loops())) {
                played_out = true;
                break;
            }
            tum->rewind();
            first_sensor_ns_ = -1;
            continue;
        }
        const double read_ms = ms_since(t_read);
        if (!pace(read.image.sensor_ns)) break;
        const Status s = publish(read.image, read_ms);
        if (!s) {
            log::error("seq=", seq_, " publishing failed: ", s.message());
        } else {
            ++stats_.published;
            log::debug("seq=", seq_, " published (", read.image.rgb_path, ")");
        }
        if (!required_.empty()) wait_for_answers(seq_);
        if (!service::stop_requested()) record_done(read.image.sensor_ns, false);
        if (seq_ % 30 == 0) (void)guard_.check_and_report();  // a writer that raced our start
        ++seq_;
    }
    stats_.elapsed_s = std::chrono::duration<double>(Clock::now() - t_start).count();
    if (played_out) record_done(-1, true);
    (void)sleep_unless_stopped(config_.linger_s());
    return stats_;
}

}  // namespace df::capture
