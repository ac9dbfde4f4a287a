#include "subscription.hpp"

#include <chrono>

#include "core/log.hpp"
#include "dds/sample_check.hpp"
#include "discovery.hpp"
#include "service/service.hpp"

namespace df::tap {

Result<Subscription> subscribe(const dds::Participant& participant, const std::string& topic,
                               double wait_s, int depth) {
    auto type_name = find_topic_type(participant, topic, wait_s);
    if (!type_name) return type_name.status();
    const dds::TypeInfo* type = dds::find_type(*type_name);
    if (type == nullptr) {
        return Status(StatusCode::kInvalidArgument, "topic '" + topic + "' has type " + *type_name +
                                                        ", which is not a DetectFusion type");
    }
    dds::EndpointOptions options{dds::QosProfile::kTap, depth};
    auto reader = dds::create_reader(participant, type->descriptor, topic, options);
    if (!reader) return reader.status();
    return Subscription{topic, type, std::move(*reader)};
}

namespace {

/// Whether a sample passed its check; a rejected one is logged (rate-limited) and not handed on,
/// so printing, recording or counting never reads past a sample's buffers.
bool accept(const Subscription& sub, const void* sample, const dds_sample_info_t& info,
            dds::RejectLog& rejects) {
    if (!info.valid_data) return true;
    const Status s = dds::check_sample(*sub.type, sample);
    if (s) return true;
    rejects.report(sub.topic, dds::writer_of(sub.reader.get(), info),
                   static_cast<const df_msg_Header*>(sample)->seq, s);
    return false;
}

}  // namespace

Status run_loop(const dds::Participant& participant, std::vector<Subscription>& subs,
                const RunLimits& limits,
                const std::function<void(size_t, const void*, const dds_sample_info_t&)>& on_sample,
                const std::function<void()>& on_tick) {
    using Clock = std::chrono::steady_clock;
    auto ws = dds::WaitSet::create(participant);
    if (!ws) return ws.status();
    for (auto& s : subs) DF_RETURN_IF_ERROR(ws->attach_reader(s.reader.get()));
    const auto start = Clock::now();
    auto last_tick = start;
    auto last_sample = start;
    bool any = false;
    uint64_t total = 0;
    dds::RejectLog rejects;
    while (!service::stop_requested()) {
        auto n = ws->wait(DDS_MSECS(50));
        if (!n) return n.status();
        for (size_t i = 0; i < subs.size(); ++i) {
            auto taken = dds::take_samples(subs[i].reader.get(), subs[i].type->descriptor,
                                           dds::ReadMode::kZeroCopy, 16,
                                           [&](const void* sample, const dds_sample_info_t& info) {
                                               if (!accept(subs[i], sample, info, rejects)) return;
                                               if (limits.count == 0 || total < limits.count)
                                                   on_sample(i, sample, info);
                                               ++total;
                                           });
            if (!taken) return taken.status();
            if (*taken > 0) {
                any = true;
                last_sample = Clock::now();
            }
        }
        const auto now = Clock::now();
        if (now - last_tick >= std::chrono::seconds(1)) {
            last_tick = now;
            if (on_tick) on_tick();
        }
        if (limits.count > 0 && total >= limits.count) break;
        if (limits.duration_s > 0 &&
            now - start >= std::chrono::duration<double>(limits.duration_s))
            break;
        if (limits.idle_s > 0 && any &&
            now - last_sample >= std::chrono::duration<double>(limits.idle_s))
            break;
    }
    return Status::ok();
}

}  // namespace df::tap
