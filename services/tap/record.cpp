// tap record: topics -> MCAP (cdr messages, omgidl schemas), optionally acknowledging frames so
// that a lockstep capture waits for the recorder.
#include <algorithm>
#include <cstdio>
#include <map>

#include "commands.hpp"
#include "core/log.hpp"
#include "dds/cdr.hpp"
#include "dds/msg_convert.hpp"
#include "dds/writer.hpp"
#include "df_msgs_idl_text.hpp"
#include "discovery.hpp"
#include "foxglove_feed.hpp"
#include "mcap/mcap_writer.hpp"

namespace df::tap {
namespace {

struct TopicStats {
    uint64_t count = 0;
    uint64_t first_ns = 0, last_ns = 0;
    std::vector<double> delay_ms;
};

Result<std::vector<Subscription>> subscribe_all(const dds::Participant& p, const RecordOptions& r,
                                                const CommonOptions& o) {
    std::vector<std::string> names = r.topics;
    if (names.empty()) {
        for (const auto& [name, info] : discover(p, o.wait_s)) {
            if (dds::find_type(info.type) != nullptr && !info.writers.empty())
                names.push_back(name);
        }
        if (names.empty()) {
            return Status(StatusCode::kNotFound,
                          "no DetectFusion topics with writers found within " +
                              std::to_string(o.wait_s) + " s");
        }
    }
    std::vector<Subscription> subs;
    for (const auto& n : names) {
        auto s = subscribe(p, n, o.wait_s, 64);
        if (!s) return s.status();
        subs.push_back(std::move(*s));
    }
    return subs;
}

/// The Foxglove channels of a recording, made on first use: one per (namespace, view).
class FoxgloveChannels {
  public:
    FoxgloveChannels(mcap::Writer& writer, const foxglove::SceneOptions& options)
        : writer_(writer), options_(options) {}
    /// Writes the views one sample made; `ns` is its topic's namespace.
    Status write(const std::string& ns, const std::vector<foxglove::Message>& messages,
                 uint32_t sequence, uint64_t log_ns) {
        for (const foxglove::Message& m : messages) {
            auto channel = channel_of(ns, m.channel);
            if (!channel) return channel.status();
            DF_RETURN_IF_ERROR(writer_.write(*channel, sequence, log_ns,
                                             static_cast<uint64_t>(m.stamp_ns), m.data.data(),
                                             m.data.size()));
        }
        return Status::ok();
    }

  private:
    Result<uint16_t> channel_of(const std::string& ns, foxglove::Channel c) {
        const auto key = std::make_pair(ns, static_cast<int>(c));
        if (auto it = ids_.find(key); it != ids_.end()) return it->second;
        const std::string prefix = ns.empty() ? "foxglove" : ns + "/foxglove";
        const foxglove::ChannelSpec spec = foxglove::channel_spec(c, prefix, options_);
        auto schema = writer_.add_schema(spec.schema, "omgidl", foxglove::idl_text());
        if (!schema) return schema.status();
        auto channel = writer_.add_channel(*schema, spec.topic, "cdr");
        if (!channel) return channel.status();
        ids_[key] = *channel;
        return *channel;
    }

    mcap::Writer& writer_;
    foxglove::SceneOptions options_;
    std::map<std::pair<std::string, int>, uint16_t> ids_;
};

double pct(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

}  // namespace

int cmd_record(const dds::Participant& p, const RecordOptions& r, const CommonOptions& o) {
    auto subs = subscribe_all(p, r, o);
    if (!subs) {
        log::error(subs.status().message());
        return 1;
    }
    mcap::WriterOptions wo;
    if (r.zstd) wo.compression = mcap::WriterOptions::Compression::kZstd;
    auto writer = mcap::Writer::open(r.output, wo);
    if (!writer) {
        log::error(writer.status().message());
        return 1;
    }
    std::vector<uint16_t> channel_of;
    for (const auto& s : *subs) {
        auto schema = (*writer)->add_schema(s.type->name, "omgidl", msg::kIdlText);
        if (!schema) return log::error(schema.status().message()), 1;
        auto channel = (*writer)->add_channel(*schema, s.topic, "cdr");
        if (!channel) return log::error(channel.status().message()), 1;
        channel_of.push_back(*channel);
        log::info("recording ", s.topic, " (", s.type->name, ") to ", r.output);
    }
    std::unique_ptr<dds::Writer<df_msg_StageStatus>> ack;
    if (!r.ack_stage.empty()) {
        auto w = dds::Writer<df_msg_StageStatus>::create(
            p, dds::topic_name(r.ns, dds::topics::kStageStatus));
        if (!w) return log::error(w.status().message()), 1;
        ack = std::make_unique<dds::Writer<df_msg_StageStatus>>(std::move(*w));
    }

    std::unique_ptr<foxglove::SceneEncoder> scene;
    std::unique_ptr<FoxgloveChannels> views;
    if (r.foxglove) {
        scene = std::make_unique<foxglove::SceneEncoder>(r.scene);
        views = std::make_unique<FoxgloveChannels>(**writer, r.scene);
        log::info("recording Foxglove views on <ns>/foxglove/{color,depth,detections,masks,tf,",
                  "scene,map}");
    }
    std::map<size_t, TopicStats> stats;
    Status write_error;
    const Status s = run_loop(
        p, *subs, o.limits,
        [&](size_t i, const void* sample, const dds_sample_info_t& info) {
            const uint64_t now = dds::wall_ns();
            const auto* header = static_cast<const df_msg_Header*>(sample);
            const std::vector<uint8_t> cdr = dds::to_cdr((*subs)[i].type->descriptor, sample);
            if (cdr.empty()) {
                log::warn("seq=", header->seq, " ", (*subs)[i].topic,
                          ": sample not recorded, a field holds a value its type does not allow");
                return;
            }
            const Status w = (*writer)->write(channel_of[i], static_cast<uint32_t>(header->seq),
                                              now, static_cast<uint64_t>(info.source_timestamp),
                                              cdr.data(), cdr.size());
            if (!w && write_error.is_ok()) write_error = w;
            if (views && has_foxglove_view(*(*subs)[i].type)) {
                const Status v = views->write(topic_ns((*subs)[i].topic),
                                              foxglove_view(*scene, *(*subs)[i].type, sample),
                                              static_cast<uint32_t>(header->seq), now);
                if (!v && write_error.is_ok()) write_error = v;
            }
            TopicStats& st = stats[i];
            if (st.count++ == 0) st.first_ns = now;
            st.last_ns = now;
            st.delay_ms.push_back(
                (static_cast<double>(now) - static_cast<double>(header->capture_ns)) * 1e-6);
            if (ack && (*subs)[i].type->descriptor == &df_msg_RgbdFrame_desc) {
                df_msg_StageStatus a{};
                a.header = *header;
                dds::set_name(a.stage, r.ack_stage);
                (void)ack->write_copy(a);
            }
        },
        nullptr);
    const Status closed = (*writer)->close();
    if (!s || !write_error || !closed) {
        log::error(!s ? s.message() : !write_error ? write_error.message() : closed.message());
        return 1;
    }
    std::printf("recorded %s (%llu messages, %.1f MB)\n", r.output.c_str(),
                static_cast<unsigned long long>((*writer)->message_count()),
                static_cast<double>((*writer)->bytes_written()) / 1e6);
    for (size_t i = 0; i < subs->size(); ++i) {
        const TopicStats& st = stats[i];
        const double span = (st.last_ns - st.first_ns) * 1e-9;
        std::printf("  %-28s %6llu msgs  %7.2f Hz  delay from capture: p50 %.3f ms  p99 %.3f ms\n",
                    (*subs)[i].topic.c_str(), static_cast<unsigned long long>(st.count),
                    st.count > 1 && span > 0 ? (st.count - 1) / span : 0.0, pct(st.delay_ms, 0.5),
                    pct(st.delay_ms, 0.99));
    }
    return 0;
}

}  // namespace df::tap
