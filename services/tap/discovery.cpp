#include "discovery.hpp"

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "dds/dds_error.hpp"

namespace df::tap {
namespace {

std::string guid_key(const dds_guid_t& g) {
    return std::string(reinterpret_cast<const char*>(g.v), 16);
}

std::string prop(const dds_qos_t* qos, const char* name) {
    char* value = nullptr;
    if (qos != nullptr && dds_qget_prop(qos, name, &value) && value != nullptr) {
        std::string v(value);
        dds_free(value);
        return v;
    }
    return "?";
}

struct Snapshot {
    std::map<std::string, EndpointInfo> participants;  // guid -> info
    struct Ep {
        std::string topic, type, participant;
        bool writer;
    };
    std::map<std::string, Ep> endpoints;  // guid -> endpoint
};

void read_participants(dds_entity_t reader, Snapshot* snap) {
    void* samples[64] = {};
    dds_sample_info_t infos[64];
    const int n = dds_read(reader, samples, infos, 64, 64);
    for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* p = static_cast<const dds_builtintopic_participant_t*>(samples[i]);
        snap->participants[guid_key(p->key)] = {
            prop(p->qos, "__Hostname"),
            prop(p->qos, "__ProcessName") + " (pid " + prop(p->qos, "__Pid") + ")"};
    }
    if (n > 0) dds_return_loan(reader, samples, n);
}

void read_endpoints(dds_entity_t reader, bool writers, Snapshot* snap) {
    void* samples[64] = {};
    dds_sample_info_t infos[64];
    const int n = dds_read(reader, samples, infos, 64, 64);
    for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data || infos[i].instance_state != DDS_IST_ALIVE) continue;
        const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
        if (std::strncmp(e->topic_name, "DCPS", 4) == 0) continue;
        snap->endpoints[guid_key(e->key)] = {e->topic_name, e->type_name,
                                             guid_key(e->participant_key), writers};
    }
    if (n > 0) dds_return_loan(reader, samples, n);
}

}  // namespace

std::map<std::string, TopicInfo> discover(const dds::Participant& participant, double wait_s) {
    dds::Entity pr(
        dds_create_reader(participant.get(), DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr));
    dds::Entity wr(
        dds_create_reader(participant.get(), DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr));
    dds::Entity rr(
        dds_create_reader(participant.get(), DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, nullptr, nullptr));
    std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
    Snapshot snap;
    read_participants(pr.get(), &snap);
    read_endpoints(wr.get(), true, &snap);
    read_endpoints(rr.get(), false, &snap);

    dds_guid_t own{};
    dds_get_guid(participant.get(), &own);
    std::map<std::string, TopicInfo> topics;
    for (const auto& [guid, ep] : snap.endpoints) {
        if (ep.participant == guid_key(own)) continue;
        TopicInfo& t = topics[ep.topic];
        t.name = ep.topic;
        t.type = ep.type;
        auto it = snap.participants.find(ep.participant);
        EndpointInfo info = it != snap.participants.end() ? it->second : EndpointInfo{"?", "?"};
        (ep.writer ? t.writers : t.readers).push_back(info);
    }
    return topics;
}

Result<std::string> find_topic_type(const dds::Participant& participant, const std::string& topic,
                                    double wait_s) {
    dds::Entity wr(
        dds_create_reader(participant.get(), DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
    std::vector<std::string> seen;
    do {
        Snapshot snap;
        read_endpoints(wr.get(), true, &snap);
        seen.clear();
        for (const auto& [guid, ep] : snap.endpoints) {
            if (ep.topic == topic) return ep.type;
            seen.push_back(ep.topic);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    } while (std::chrono::steady_clock::now() < deadline);
    std::string names;
    for (const auto& s : seen) names += (names.empty() ? "" : ", ") + s;
    return Status(StatusCode::kNotFound,
                  "no writer of topic '" + topic + "' found within " + std::to_string(wait_s) +
                      " s (topics with writers: " + (names.empty() ? "none" : names) + ")");
}

}  // namespace df::tap
