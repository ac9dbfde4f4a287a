#include "geoseg_node.hpp"

#include <chrono>
#include <vector>

#include "config/apply_params.hpp"
#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "service/service.hpp"
#include "slam/frame.hpp"

namespace df::geoseg_service {
namespace {

int64_t now_ns() { return service::steady_ns(); }

double ms_since(int64_t start_ns) { return static_cast<double>(now_ns() - start_ns) * 1e-6; }

struct Pending {
    io::RgbdImage image;
    df_msg_Header header;
    bool valid = true;  ///< false: the sample failed its check (answered as failed)
};

}  // namespace

Status apply(const config::GeosegParams& p, seg::GeometricSegmentationConfig* seg,
             slam::PreprocessConfig* preprocess) {
    DF_RETURN_IF_ERROR(config::apply_params(p, seg));
    preprocess->max_depth_m = seg->max_depth_m;
    preprocess->normal_baseline_px = seg->normal_baseline_px;
    preprocess->pyramid_levels = 1;  // only the full-resolution level is segmented
    if (std::string e = seg::validate(*seg); !e.empty()) {
        return error(StatusCode::kInvalidArgument, "params: " + e);
    }
    if (std::string e = slam::validate(*preprocess); !e.empty()) {
        return error(StatusCode::kInvalidArgument, "params: " + e);
    }
    return Status::ok();
}

Result<std::unique_ptr<GeosegNode>> GeosegNode::create(const config::GeosegServiceConfig& config,
                                                       const seg::GeometricSegmentationConfig& seg,
                                                       const slam::PreprocessConfig& preprocess,
                                                       dds::Participant& participant) {
    const std::string& ns = config.dds().ns();
    auto frames = dds::Reader<df_msg_RgbdFrame>::create(participant,
                                                        dds::topic_name(ns, dds::topics::kFrames));
    if (!frames) return frames.status();
    auto segments = dds::Writer<df_msg_GeometricSegments>::create(
        participant, dds::topic_name(ns, dds::topics::kGeometricSegments));
    if (!segments) return segments.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(frames->get()));
    return std::unique_ptr<GeosegNode>(new GeosegNode(config, seg, preprocess, std::move(*frames),
                                                      std::move(*segments), std::move(*status),
                                                      std::move(*waitset)));
}

GeosegNode::GeosegNode(const config::GeosegServiceConfig& config,
                       const seg::GeometricSegmentationConfig& seg,
                       const slam::PreprocessConfig& preprocess,
                       dds::Reader<df_msg_RgbdFrame> frames,
                       dds::Writer<df_msg_GeometricSegments> segments,
                       dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset)
    : config_(config),
      seg_(seg),
      preprocess_(preprocess),
      frames_(std::move(frames)),
      segments_(std::move(segments)),
      status_(std::move(status)),
      waitset_(std::move(waitset)) {}

void GeosegNode::answer(const df_msg_Header& header, df_msg_FrameStatus status) {
    auto loan = segments_.loan();
    if (loan) {
        df_msg_GeometricSegments& m = **loan;
        m.header = header;
        m.header.status = status;
        m.width = m.height = 0;
        m.segment_count = 0;
        if (Status s = segments_.write(std::move(*loan)); !s)
            log::warn("seq=", header.seq, " ", s.message());
    }
    df_msg_StageStatus st{};
    st.header = header;
    st.header.status = status;
    dds::set_name(st.stage, config_.stage());
    (void)status_.write_copy(st);
}

void GeosegNode::answer_missed(const df_msg_Header& header) {
    const std::vector<uint64_t> missed = gaps_.arrived(header.epoch, header.seq);
    if (missed.empty()) return;
    log::info("seq=", header.seq, " frames ", missed.front(), "..", missed.back(),
              " never reached this stage (the reader fell behind): answered skipped");
    df_msg_Header h = header;
    for (uint64_t seq : missed) {
        h.seq = seq;
        ++skipped_;
        answer(h, df_msg_FRAME_SKIPPED);
    }
}

void GeosegNode::handle(const io::RgbdImage& image, const df_msg_Header& header) {
    const int64_t t0 = now_ns();
    auto frame = slam::preprocess(image, preprocess_);
    if (!frame) {
        log::error("seq=", header.seq, " ", frame.status().message());
        ++failed_;
        answer(header, df_msg_FRAME_FAILED);
        return;
    }
    const double preprocess_ms = ms_since(t0);
    const int64_t t1 = now_ns();
    const slam::FrameLevel& level = frame->levels[0];
    auto g = seg::segment_geometry(level.smoothed_vertex, level.normal, seg_);
    if (!g) {
        log::error("seq=", header.seq, " ", g.status().message());
        ++failed_;
        answer(header, df_msg_FRAME_FAILED);
        return;
    }
    const double segment_ms = ms_since(t1);
    auto loan = segments_.loan();
    if (!loan) {
        log::error("seq=", header.seq, " no sample to publish: ", loan.status().message());
        ++failed_;
        return;
    }
    df_msg_GeometricSegments& m = **loan;
    m.header = header;
    m.header.status = df_msg_FRAME_OK;
    m.width = static_cast<uint16_t>(g->labels.cols);
    m.height = static_cast<uint16_t>(g->labels.rows);
    // Labels are 1..count; more than 65535 segments cannot happen at MAX_PIXELS with the
    // minimum segment size, but clamp anyway.
    m.segment_count = static_cast<uint32_t>(std::min(g->count, 65535));
    uint16_t* out = m.labels;
    for (int y = 0; y < g->labels.rows; ++y) {
        const int32_t* l = g->labels.ptr<int32_t>(y);
        for (int x = 0; x < g->labels.cols; ++x)
            *out++ = static_cast<uint16_t>(std::min(l[x], 65535));
    }
    if (Status s = segments_.write(std::move(*loan)); !s)
        log::warn("seq=", header.seq, " ", s.message());
    ++processed_;
    df_msg_StageStatus st{};
    st.header = header;
    st.header.status = df_msg_FRAME_OK;
    dds::set_name(st.stage, config_.stage());
    st.timing_count = 3;
    dds::set_name(st.timings[0].name, "preprocess");
    st.timings[0].ms = static_cast<float>(preprocess_ms);
    dds::set_name(st.timings[1].name, "segment");
    st.timings[1].ms = static_cast<float>(segment_ms);
    dds::set_name(st.timings[2].name, "total");
    st.timings[2].ms = static_cast<float>(ms_since(t0));
    (void)status_.write_copy(st);
}

Status GeosegNode::run() {
    log::info("waiting for frames on ", frames_.topic());
    service::StreamEnd stream(config_.idle_exit_s(), config_.writers_grace_s());
    while (!service::stop_requested()) {
        auto woke = waitset_.wait(DDS_MSECS(100));
        if (!woke) return woke.status();
        std::vector<Pending> pending;
        auto taken = frames_.take_batch(
            [&](const df_msg_RgbdFrame& f, const dds_sample_info_t& info, bool newest) {
                if (!info.valid_data) return;
                auto frame = dds::accept(f, frames_.get(), frames_.topic(), info, rejects_);
                if (!frame)
                    pending.push_back({{}, f.header, false});
                else if (newest)  // only the newest is segmented: only it leaves the loan
                    pending.push_back({dds::to_image(*frame), f.header});
                else
                    pending.push_back({{}, f.header});
            },
            16);
        if (!taken) return taken.status();
        for (size_t i = 0; i < pending.size(); ++i) {
            stream.on_input();
            if (!pending[i].valid) {
                ++failed_;
                answer(pending[i].header, df_msg_FRAME_FAILED);
                continue;
            }
            answer_missed(pending[i].header);
            if (i + 1 < pending.size()) {
                ++skipped_;
                answer(pending[i].header, df_msg_FRAME_SKIPPED);
            } else {
                handle(pending[i].image, pending[i].header);
            }
        }
        if (const char* why = stream.check(frames_.matched_writers(), pending.empty())) {
            log::info("stream ended (", why, "): ", processed_, " frames segmented, ", skipped_,
                      " skipped, ", failed_, " failed (",
                      gaps_.missed(), " of the skipped never reached the reader)");
            if (config_.exit_at_end()) return Status::ok();
            stream.reset();
            gaps_ = {};
            processed_ = skipped_ = failed_ = 0;
        }
    }
    return Status::ok();
}

}  // namespace df::geoseg_service
