#pragma once
/// A DDS domain participant with the project's transport set-up.
///
/// Transport choice (logged at start):
///  - env CYCLONEDDS_URI set: that configuration is used as the user wrote it;
///  - kSharedMemory: iceoryx shared memory for local readers + UDP for remote ones;
///    requires a running RouDi (deploy/config/roudi.toml), else a clear error instead of
///    Cyclone's 60 s wait and abort;
///  - kUdp: network only;
///  - kAuto (default): shared memory when RouDi is running, else UDP.
#include <string>

#include "core/status.hpp"
#include "dds/entity.hpp"

namespace df::dds {

enum class Transport { kAuto, kSharedMemory, kUdp };

/// Parses "auto", "shm", "udp" (as in flags and config files).
Result<Transport> parse_transport(const std::string& text);
const char* to_string(Transport t);

struct ParticipantConfig {
    uint32_t domain_id = 0;
    Transport transport = Transport::kAuto;
    /// Extra Cyclone XML put inside <Domain> (e.g. <General><Interfaces>...,
    /// <Discovery><Peers>...).
    std::string extra_xml;
    /// Lock file RouDi holds while it runs (iceoryx 2.0).
    std::string roudi_lock_file = "/tmp/roudi.lock";
};

/// True when a RouDi daemon holds its lock file (it is running on this machine).
bool roudi_running(const std::string& lock_file = "/tmp/roudi.lock");

class Participant {
  public:
    static Result<Participant> create(const ParticipantConfig& config);

    dds_entity_t get() const { return participant_.get(); }
    /// The transport in effect: kSharedMemory or kUdp (kAuto when the user's CYCLONEDDS_URI
    /// decides).
    Transport transport() const { return transport_; }
    bool shared_memory_enabled() const { return transport_ == Transport::kSharedMemory; }

  private:
    Participant(Entity domain, Entity participant, Transport t)
        : domain_(std::move(domain)), participant_(std::move(participant)), transport_(t) {}
    // Declared first, destroyed last: the participant goes before its domain.
    Entity domain_;
    Entity participant_;
    Transport transport_ = Transport::kUdp;
};

}  // namespace df::dds
