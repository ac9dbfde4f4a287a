#pragma once
/// Untyped building blocks of the typed Writer<T>/Reader<T>: topic, writer and reader creation
/// with the project's QoS, and the log line that says which path (loan / copy / network) is used.
#include <dds/ddsc/dds_loan_api.h>

#include <chrono>
#include <string>

#include "dds/entity.hpp"
#include "dds/participant.hpp"
#include "dds/qos.hpp"

namespace df::dds {

struct EndpointOptions {
    QosProfile profile = QosProfile::kResults;
    int32_t depth = 0;                  ///< history depth; 0 = the profile's default
    bool allow_loans = true;            ///< writers: loan from shared memory when possible
    dds_duration_t latency_budget = 0;  ///< > 0 lets local shm delivery go before remote sends
};

/// Creates (or finds) the topic and a writer on it; logs "writer <topic>: <path>".
Result<Entity> create_writer(const Participant& participant, const dds_topic_descriptor_t* desc,
                             const std::string& topic, const EndpointOptions& options);
/// Creates (or finds) the topic and a reader on it; logs "reader <topic>: <path>".
Result<Entity> create_reader(const Participant& participant, const dds_topic_descriptor_t* desc,
                             const std::string& topic, const EndpointOptions& options);

/// Number of matched readers of a writer / writers of a reader (0 on error).
uint32_t matched_readers(dds_entity_t writer);
uint32_t matched_writers(dds_entity_t reader);

/// Time for iceoryx subscriptions to connect after DDS reports a shared-memory match (300 ms
/// lost the first of 30 replayed frames in record_play_test while a SLAM test held both cores).
inline constexpr std::chrono::milliseconds kShmConnectSettle{1000};

/// Waits until a writer has at least n matched readers (or a reader n writers), and over shared
/// memory until they are connected (kShmConnectSettle).
Status wait_for_matches(dds_entity_t endpoint, bool is_writer, uint32_t n, dds_duration_t timeout);

}  // namespace df::dds
