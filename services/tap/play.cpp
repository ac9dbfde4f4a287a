// tap play: an MCAP recording back onto its topics (or remapped ones) at original or scaled rate.
// Every message is decoded and checked (decode_recorded) before it is written: a corrupt one is
// logged naming file, message and field, not published, and the play goes on; the exit code is
// then 1.
#include <dds/ddsc/dds_loan_api.h>

#include <chrono>
#include <cstring>
#include <map>
#include <thread>

#include "commands.hpp"
#include "core/log.hpp"
#include "dds/dds_error.hpp"
#include "dds/endpoint.hpp"
#include "mcap/mcap_reader.hpp"
#include "recorded_sample.hpp"
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
    std::string recorded_topic;  ///< the channel's topic in the file (before --remap)
    std::vector<unsigned char> scratch;
};

/// What became of one recorded message that did not fail to write.
struct Outcome {
    Status rejected;  ///< ok: written; else decode_recorded()'s error, and it was not written
};

/// Decodes and checks one message into a loaned (or scratch) sample and writes it; a message
/// that fails its check is never written (a loan is returned unwritten). Error: the write failed.
Result<Outcome> publish(Output& out, const mcap::Message& m, const RecordRef& where) {
    const dds_topic_descriptor_t* desc = out.type->descriptor;
    if (out.loans) {
        void* sample = nullptr;
        if (dds_loan_sample(out.writer.get(), &sample) == DDS_RETCODE_OK && sample != nullptr) {
            std::memset(sample, 0, desc->m_size);
            const Status s = decode_recorded(*out.type, m, where, sample);
            if (!s) {
                dds_return_loan(out.writer.get(), &sample, 1);
                return Outcome{s};
            }
            DF_RETURN_IF_ERROR(dds::check(dds_write(out.writer.get(), sample), "writing"));
            return Outcome{};
        }
    }
    out.scratch.assign(desc->m_size + 16, 0);
    void* sample = out.scratch.data();
    const Status s = decode_recorded(*out.type, m, where, sample);
    const Status w = s ? dds::check(dds_write(out.writer.get(), sample), "writing") : Status::ok();
    dds_sample_free(sample, desc, DDS_FREE_CONTENTS);
    if (!s) return Outcome{s};
    DF_RETURN_IF_ERROR(w);
    return Outcome{};
}

/// A writer per DetectFusion cdr channel of the file (by channel id), on its remapped topic.
Result<std::map<uint16_t, Output>> open_outputs(const dds::Participant& p,
                                                const mcap::Reader& reader,
                                                const PlayOptions& play) {
    std::map<uint16_t, Output> outputs;
    for (const auto& [id, ch] : reader.channels()) {
        auto schema = reader.schemas().find(ch.schema_id);
        const dds::TypeInfo* type =
            schema == reader.schemas().end() ? nullptr : dds::find_type(schema->second.name);
        if (type == nullptr || ch.message_encoding != "cdr") {
            log::warn("skipping channel ", ch.topic, ": not a DetectFusion cdr topic");
            continue;
        }
        const std::string topic = remap(ch.topic, play.remaps);
        auto w = dds::create_writer(p, type->descriptor, topic, {type->profile});
        if (!w) return w.status();
        Output out;
        out.type = type;
        out.loans = type->fixed_size() && dds_is_loan_available(w->get());
        out.writer = std::move(*w);
        out.recorded_topic = ch.topic;
        log::info("playing ", ch.topic, " -> ", topic, " (", type->name, ")");
        outputs.emplace(id, std::move(out));
    }
    return outputs;
}

/// Corrupt messages logged one line each; after that many only counted (a hostile file of a
/// million bad records must not flood the log).
constexpr uint64_t kCorruptLinesLogged = 20;

}  // namespace

int cmd_play(const dds::Participant& p, const PlayOptions& play) {
    auto reader = mcap::Reader::open(play.input);
    if (!reader) return log::error(reader.status().message()), 1;
    auto opened = open_outputs(p, **reader, play);
    if (!opened) return log::error(opened.status().message()), 1;
    std::map<uint16_t, Output>& outputs = *opened;
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
    uint64_t index = 0;  // every message of the file, played or not
    uint64_t corrupt = 0;
    Status failure;
    const Status s = (*reader)->for_each_message([&](const mcap::Message& m) {
        if (service::stop_requested()) return false;
        const uint64_t this_index = index++;
        auto it = outputs.find(m.channel_id);
        if (it == outputs.end()) return true;
        if (first_log == 0) first_log = m.log_time_ns;
        if (play.rate > 0) {
            const auto due = start + std::chrono::nanoseconds(static_cast<int64_t>(
                                         (m.log_time_ns - first_log) / play.rate));
            std::this_thread::sleep_until(due);
        }
        const RecordRef where{play.input, this_index, it->second.recorded_topic};
        auto published = publish(it->second, m, where);
        if (!published) {
            failure = published.status().with_context("message " + std::to_string(this_index) +
                                                      " on " + it->second.recorded_topic);
            return false;
        }
        if (!published->rejected) {
            if (corrupt++ < kCorruptLinesLogged) {
                log::error("play: ", published->rejected.message(), "; not published");
                if (corrupt == kCorruptLinesLogged)
                    log::error("play: further corrupt messages are counted, not logged");
            }
            return true;
        }
        ++played;
        return true;
    });
    if (!s || !failure) return log::error(!s ? s.message() : failure.message()), 1;
    for (auto& [id, out] : outputs) dds_wait_for_acks(out.writer.get(), DDS_SECS(2));
    if (corrupt > 0) {
        log::error("play: ", play.input, ": ", corrupt,
                   " message(s) failed their check and were not published; played ", played);
        return 1;
    }
    log::info("played ", played, " messages from ", play.input);
    return 0;
}

}  // namespace df::tap
