#include "timing_recording.hpp"

#include <cstring>
#include <fstream>

#include "dds/cdr.hpp"
#include "dds/msg_types.hpp"
#include "mcap/mcap_reader.hpp"

namespace df::eval_cli {

bool is_mcap_file(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[8] = {};
    in.read(magic, sizeof magic);
    return in && std::memcmp(magic, "\x89MCAP0\r\n", 8) == 0;
}

Result<std::vector<eval::TimingSample>> read_timing_recording(const std::string& file) {
    auto reader = mcap::Reader::open(file);
    if (!reader) return reader.status();
    std::vector<uint16_t> channels;
    for (const auto& [id, ch] : (*reader)->channels()) {
        auto schema = (*reader)->schemas().find(ch.schema_id);
        if (schema != (*reader)->schemas().end() && schema->second.name == "df::msg::StageStatus" &&
            ch.message_encoding == "cdr") {
            channels.push_back(id);
        }
    }
    if (channels.empty()) {
        return Status(StatusCode::kNotFound,
                      "recording '" + file +
                          "' has no df::msg::StageStatus channel (record <ns>/stage_status)");
    }
    std::vector<eval::TimingSample> samples;
    Status failure;
    const Status s = (*reader)->for_each_message([&](const mcap::Message& m) {
        if (std::find(channels.begin(), channels.end(), m.channel_id) == channels.end()) return true;
        df_msg_StageStatus st{};
        const Status d = dds::from_cdr(&df_msg_StageStatus_desc, m.data, m.size, &st);
        if (!d) {
            failure = d.with_context("recording '" + file + "', message at log time " +
                                     std::to_string(m.log_time_ns));
            return false;
        }
        eval::TimingSample sample;
        sample.seq = static_cast<int64_t>(st.header.seq);
        sample.stage = dds::get_name(st.stage);
        for (uint32_t i = 0; i < st.timing_count && i < df_msg_MAX_STAGE_TIMINGS; ++i) {
            sample.steps_ms.emplace_back(dds::get_name(st.timings[i].name), st.timings[i].ms);
        }
        if (!sample.steps_ms.empty()) samples.push_back(std::move(sample));
        return true;
    });
    if (!s) return s;
    if (!failure) return failure;
    return samples;
}

}  // namespace df::eval_cli
