#include "dds/participant.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>

#include "core/log.hpp"
#include "dds/dds_error.hpp"

namespace df::dds {

Result<Transport> parse_transport(const std::string& text) {
    if (text == "auto") return Transport::kAuto;
    if (text == "shm" || text == "shared_memory") return Transport::kSharedMemory;
    if (text == "udp") return Transport::kUdp;
    return Status(StatusCode::kInvalidArgument,
                  "unknown transport '" + text + "' (expected auto, shm or udp)");
}

const char* to_string(Transport t) {
    switch (t) {
        case Transport::kAuto:
            return "auto";
        case Transport::kSharedMemory:
            return "shm";
        case Transport::kUdp:
            return "udp";
    }
    return "?";
}

bool roudi_running(const std::string& lock_file) {
    const int fd = ::open(lock_file.c_str(), O_RDONLY);
    if (fd < 0) return false;
    const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0;  // RouDi holds an exclusive lock
    if (!held) ::flock(fd, LOCK_UN);
    ::close(fd);
    return held;
}

namespace {

std::string domain_xml(const ParticipantConfig& config, bool shm) {
    std::string xml = "<CycloneDDS><Domain Id=\"any\">";
    if (shm) {
        xml += "<SharedMemory><Enable>true</Enable><LogLevel>warn</LogLevel></SharedMemory>";
    }
    xml += config.extra_xml;
    xml += "</Domain></CycloneDDS>";
    return xml;
}

}  // namespace

Result<Participant> Participant::create(const ParticipantConfig& config) {
    const char* user_uri = std::getenv("CYCLONEDDS_URI");
    Transport effective = config.transport;
    Entity domain;
    if (user_uri != nullptr && *user_uri != '\0') {
        log::info("DDS: using the configuration in CYCLONEDDS_URI (", user_uri, ")");
        effective = Transport::kAuto;
    } else {
        const bool roudi = roudi_running(config.roudi_lock_file);
        if (effective == Transport::kAuto) {
            effective = roudi ? Transport::kSharedMemory : Transport::kUdp;
            if (!roudi) {
                log::info("DDS: no RouDi running (", config.roudi_lock_file,
                          " not locked): using UDP; start iox-roudi for shared memory");
            }
        } else if (effective == Transport::kSharedMemory && !roudi) {
            return Status(StatusCode::kUnavailable,
                          "shared memory requested but no iceoryx RouDi is running (lock file " +
                              config.roudi_lock_file +
                              " not held): start it with 'iox-roudi -c deploy/config/roudi.toml' "
                              "or use transport udp");
        }
        const std::string xml = domain_xml(config, effective == Transport::kSharedMemory);
        const dds_entity_t d = dds_create_domain(config.domain_id, xml.c_str());
        if (d < 0) {
            return check(d, "creating DDS domain " + std::to_string(config.domain_id) +
                                " with config " + xml);
        }
        domain = Entity(d);
    }
    const dds_entity_t p = dds_create_participant(config.domain_id, nullptr, nullptr);
    if (p < 0) {
        return check(p, "creating DDS participant in domain " + std::to_string(config.domain_id));
    }
    log::info("DDS: participant in domain ", config.domain_id, ", transport ",
              to_string(effective));
    return Participant(std::move(domain), Entity(p), effective);
}

}  // namespace df::dds
