// tap play: an MCAP recording back onto its topics (or remapped ones) at original or scaled rate.
#include <dds/ddsc/dds_loan_api.h>

#include <chrono>
#include <cstring>
#include <map>
#include <thread>

#include "commands.hpp"
#include "core/log.hpp"
#include "dds/cdr.hpp"
#include "dds/dds_error.hpp"
#include "dds/endpoint.hpp"
#include "mcap/mcap_reader.hpp"
#include "service/service.hpp"

namespace df::tap {
namespace {

std::string remap(const std::string& topic, const std::vector<std::string>& remaps) {
    for (const auto& r : remaps) {
        const auto eq = r.find('=');
        if (eq == std::string::npos) continue;
        const std::string from = r.substr(0, eq);
        if (topic.compare(0, from.size(), from) == 0)
            return r.substr(eq + 1) + topic.substr(from.size());
    }
    return topic;
}

struct Output {
    const dds::TypeInfo* type = nullptr;
    dds::Entity writer;
    bool loans = false;
    std::vector<unsigned char> scratch;
};

/// Deserializes one message into a loaned (or scratch) sample and writes it.
Status publish(Output& out, const mcap::Message& m) {
    const dds_topic_descriptor_t* desc = out.type->descriptor;
    if (out.loans) {
        void* sample = nullptr;
        if (dds_loan_sample(out.writer.get(), &sample) == DDS_RETCODE_OK && sample != nullptr) {
            std::memset(sample, 0, desc->m_size);
            const Status s = dds::from_cdr(desc, m.data, m.size, sample);
            if (!s) {
                dds_return_loan(out.writer.get(), &sample, 1);
                return s;
            }
            return dds::check(dds_write(out.writer.get(), sample), "writing");
        }
    }
    out.scratch.assign(desc->m_size + 16, 0);
    void* sample = out.scratch.data();
    DF_RETURN_IF_ERROR(dds::from_cdr(desc, m.data, m.size, sample));
    const Status s = dds::check(dds_write(out.writer.get(), sample), "writing");
    dds_sample_free(sample, desc, DDS_FREE_CONTENTS);
    return s;
}

}  // namespace

int cmd_play(const dds::Participant& p, const PlayOptions& play) {
    auto reader = mcap::Reader::open(play.input);
    if (!reader) return log::error(reader.status().message()), 1;
    std::map<uint16_t, Output> outputs;
    for (const auto& [id, ch] : (*reader)->channels()) {
        auto schema = (*reader)->schemas().find(ch.schema_id);
        const dds::TypeInfo* type =
            schema == (*reader)->schemas().end() ? nullptr : dds::find_type(schema->second.name);
        if (type == nullptr || ch.message_encoding != "cdr") {
            log::warn("skipping channel ", ch.topic, ": not a DetectFusion cdr topic");
            continue;
        }
        const std::string topic = remap(ch.topic, play.remaps);
        auto w = dds::create_writer(p, type->descriptor, topic, {type->profile});
        if (!w) return log::error(w.status().message()), 1;
        Output out;
        out.type = type;
        out.loans = type->fixed_size() && dds_is_loan_available(w->get());
        out.writer = std::move(*w);
        log::info("playing ", ch.topic, " -> ", topic, " (", type->name, ")");
        outputs.emplace(id, std::move(out));
    }
    if (play.wait_readers > 0) {
        for (auto& [id, out] : outputs) {
            const Status s =
                dds::wait_for_matches(out.writer.get(), true, play.wait_readers,
                                      static_cast<dds_duration_t>(play.start_wait_s * 1e9));
            if (!s) return log::error("play: ", s.message()), 1;
        }
    }
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    uint64_t first_log = 0;
    uint64_t played = 0;
    Status failure;
    const Status s = (*reader)->for_each_message([&](const mcap::Message& m) {
        if (service::stop_requested()) return false;
        auto it = outputs.find(m.channel_id);
        if (it == outputs.end()) return true;
        if (first_log == 0) first_log = m.log_time_ns;
        if (play.rate > 0) {
            const auto due = start + std::chrono::nanoseconds(static_cast<int64_t>(
                                         (m.log_time_ns - first_log) / play.rate));
            std::this_thread::sleep_until(due);
        }
        const Status w = publish(it->second, m);
        if (!w) {
            failure = w.with_context("message " + std::to_string(played) + " on channel " +
                                     std::to_string(m.channel_id));
            return false;
        }
        ++played;
        return true;
    });
    if (!s || !failure) return log::error(!s ? s.message() : failure.message()), 1;
    for (auto& [id, out] : outputs) dds_wait_for_acks(out.writer.get(), DDS_SECS(2));
    log::info("played ", played, " messages from ", play.input);
    return 0;
}

}  // namespace df::tap
