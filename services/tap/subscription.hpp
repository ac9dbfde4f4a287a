#pragma once
/// A tap's reader on any topic of the pipeline: the type is learnt from discovery.
#include <functional>
#include <string>

#include "dds/endpoint.hpp"
#include "dds/msg_types.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"

namespace df::tap {

struct Subscription {
    std::string topic;
    const dds::TypeInfo* type = nullptr;
    dds::Entity reader;
};

/// Finds the topic's type (waiting up to wait_s for a writer) and subscribes with tap QoS
/// (best effort, keep last `depth`: matches any writer, never slows it).
Result<Subscription> subscribe(const dds::Participant& participant, const std::string& topic,
                               double wait_s, int depth = 16);

/// Stop conditions shared by the tap commands.
struct RunLimits {
    double duration_s = 0;  ///< stop after this long (0 = no limit)
    uint64_t count = 0;     ///< stop after this many samples in all (0 = no limit)
    double idle_s = 0;      ///< stop when nothing arrived for this long after the first sample
};

/// Takes samples from every subscription until a limit or a stop signal: on_sample(index of the
/// subscription, sample, info) per sample; on_tick() about once per second.
Status run_loop(const dds::Participant& participant, std::vector<Subscription>& subs,
                const RunLimits& limits,
                const std::function<void(size_t, const void*, const dds_sample_info_t&)>& on_sample,
                const std::function<void()>& on_tick);

}  // namespace df::tap
