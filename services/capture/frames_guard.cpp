#include "frames_guard.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/log.hpp"
#include "dds/dds_error.hpp"

namespace df::capture {
namespace {

constexpr size_t kMaxSamples = 64;

std::string guid_text(const dds_guid_t& g) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (size_t i = 0; i < sizeof g.v; ++i) {
        out += hex[g.v[i] >> 4];
        out += hex[g.v[i] & 15];
    }
    return out;
}

/// Reads (without taking) every alive sample of a built-in reader; fn(const T&) per sample.
template <typename T, typename Fn>
void read_alive(dds_entity_t reader, Fn&& fn) {
    void* samples[kMaxSamples] = {};
    dds_sample_info_t infos[kMaxSamples];
    const dds_return_t n = dds_read(reader, samples, infos, kMaxSamples, kMaxSamples);
    if (n <= 0) return;
    for (dds_return_t i = 0; i < n; ++i) {
        if (infos[i].valid_data && infos[i].instance_state == DDS_IST_ALIVE) {
            fn(*static_cast<const T*>(samples[i]));
        }
    }
    dds_return_loan(reader, samples, n);
}

std::string host_name() {
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) != 0) std::strcpy(host, "?");
    return host;
}

}  // namespace

std::string own_identity() {
    return "df_capture host=" + host_name() + " pid=" + std::to_string(getpid());
}

bool is_dead_local_capture(const std::string& identity) {
    const std::string prefix = "df_capture host=" + host_name() + " pid=";
    if (identity.compare(0, prefix.size(), prefix) != 0) return false;
    const std::string digits = identity.substr(prefix.size());
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
        return false;
    }
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    return pid > 0 && pid != getpid() && kill(pid, 0) != 0 && errno == ESRCH;
}

Result<FramesGuard> FramesGuard::create(dds_entity_t participant, dds_entity_t frames_writer,
                                        std::string topic) {
    dds_qos_t* qos = dds_create_qos();
    const std::string id = own_identity();
    dds_qset_userdata(qos, id.data(), id.size());
    const dds_return_t set = dds_set_qos(participant, qos);
    dds_delete_qos(qos);
    if (set != DDS_RETCODE_OK) log::warn("capture: cannot set the participant's user data");
    dds_guid_t own{};
    DF_RETURN_IF_ERROR(dds::check(dds_get_guid(frames_writer, &own), "reading the writer's GUID"));
    const dds_entity_t pubs =
        dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
    if (pubs < 0) return dds::check(pubs, "reading DCPSPublication");
    dds::Entity publications(pubs);
    const dds_entity_t parts =
        dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr);
    if (parts < 0) return dds::check(parts, "reading DCPSParticipant");
    return FramesGuard(std::move(publications), dds::Entity(parts), own, std::move(topic));
}

std::string FramesGuard::describe_participant(const dds_guid_t& key) {
    std::string out;
    read_alive<dds_builtintopic_participant_t>(
        participants_.get(), [&](const dds_builtintopic_participant_t& p) {
            if (std::memcmp(p.key.v, key.v, sizeof key.v) != 0 || p.qos == nullptr) return;
            void* data = nullptr;
            size_t size = 0;
            if (dds_qget_userdata(p.qos, &data, &size) && data != nullptr) {
                out.assign(static_cast<const char*>(data), size);
            }
            dds_free(data);
        });
    return out.empty() ? "a writer in participant " + guid_text(key) + " (not a df_capture)" : out;
}

std::vector<std::string> FramesGuard::other_writers() {
    std::vector<dds_guid_t> others;
    read_alive<dds_builtintopic_endpoint_t>(
        publications_.get(), [&](const dds_builtintopic_endpoint_t& e) {
            if (e.topic_name == nullptr || topic_ != e.topic_name) return;
            if (std::memcmp(e.key.v, own_.v, sizeof own_.v) == 0) return;
            others.push_back(e.participant_key);
        });
    std::vector<std::string> out;
    for (const dds_guid_t& p : others) {
        std::string who = describe_participant(p);
        // A capture of this host killed a moment ago (a supervisor restarts us): its writer
        // stays in discovery until its lease runs out, but no frame can come from it.
        if (is_dead_local_capture(who)) {
            if (dead_.insert(who).second) {
                log::info("capture: the writer of ", topic_, " of ", who,
                          " is still in discovery, but that process is gone (killed); going on");
            }
            continue;
        }
        out.push_back(std::move(who));
    }
    return out;
}

bool FramesGuard::check_and_report() {
    const auto others = other_writers();
    for (const std::string& o : others) {
        if (reported_.insert(o).second) {
            log::error("another writer of ", topic_, " is running: ", o,
                       "; two captures on one namespace interleave their frames");
        }
    }
    return !others.empty();
}

}  // namespace df::capture
