#include "dds/endpoint.hpp"

#include <thread>

#include "core/log.hpp"
#include "dds/dds_error.hpp"

namespace df::dds {
namespace {

Result<dds_entity_t> make_topic(const Participant& participant, const dds_topic_descriptor_t* desc,
                                const std::string& topic) {
    const dds_entity_t t =
        dds_create_topic(participant.get(), desc, topic.c_str(), nullptr, nullptr);
    if (t < 0) {
        return check(t, "creating topic '" + topic + "' of type " + desc->m_typename);
    }
    return t;
}

}  // namespace

Result<Entity> create_writer(const Participant& participant, const dds_topic_descriptor_t* desc,
                             const std::string& topic, const EndpointOptions& options) {
    auto t = make_topic(participant, desc, topic);
    if (!t) return t.status();
    QosPtr qos = make_qos(options.profile, options.depth);
    if (options.latency_budget > 0) dds_qset_latency_budget(qos.get(), options.latency_budget);
    const dds_entity_t w = dds_create_writer(participant.get(), *t, qos.get(), nullptr);
    if (w < 0) return check(w, "creating writer on '" + topic + "'");
    const bool shm = dds_is_shared_memory_available(w);
    const bool loan = options.allow_loans && dds_is_loan_available(w);
    log::info("writer ", topic, " (", desc->m_typename, ", qos ", to_string(options.profile), "): ",
              loan  ? "shared memory, loaned samples (zero-copy)"
              : shm ? "shared memory, samples copied in"
                    : "network (UDP), samples serialized");
    return Entity(w);
}

Result<Entity> create_reader(const Participant& participant, const dds_topic_descriptor_t* desc,
                             const std::string& topic, const EndpointOptions& options) {
    auto t = make_topic(participant, desc, topic);
    if (!t) return t.status();
    QosPtr qos = make_qos(options.profile, options.depth);
    if (options.latency_budget > 0) dds_qset_latency_budget(qos.get(), options.latency_budget);
    const dds_entity_t r = dds_create_reader(participant.get(), *t, qos.get(), nullptr);
    if (r < 0) return check(r, "creating reader on '" + topic + "'");
    const bool shm = dds_is_shared_memory_available(r);
    log::info("reader ", topic, " (", desc->m_typename, ", qos ", to_string(options.profile), "): ",
              shm ? "shared memory for local writers, UDP for remote ones" : "network (UDP)");
    return Entity(r);
}

uint32_t matched_readers(dds_entity_t writer) {
    dds_publication_matched_status_t s{};
    if (dds_get_publication_matched_status(writer, &s) < 0) return 0;
    return s.current_count;
}

uint32_t matched_writers(dds_entity_t reader) {
    dds_subscription_matched_status_t s{};
    if (dds_get_subscription_matched_status(reader, &s) < 0) return 0;
    return s.current_count;
}

Status wait_for_matches(dds_entity_t endpoint, bool is_writer, uint32_t n, dds_duration_t timeout) {
    const dds_time_t deadline = dds_time() + timeout;
    while (true) {
        const uint32_t have = is_writer ? matched_readers(endpoint) : matched_writers(endpoint);
        if (have >= n) break;
        if (dds_time() >= deadline) {
            return Status(StatusCode::kTimeout,
                          std::string("waited ") + std::to_string(timeout / DDS_NSECS_IN_MSEC) +
                              " ms for " + std::to_string(n) +
                              (is_writer ? " reader(s)" : " writer(s)") + ", found " +
                              std::to_string(have));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    // Over shared memory DDS reports the match a little before the peer's iceoryx subscription is
    // connected; a sample sent in between is lost (seen under load). Give it time to connect.
    if (dds_is_shared_memory_available(endpoint)) std::this_thread::sleep_for(kShmConnectSettle);
    return Status::ok();
}

}  // namespace df::dds
