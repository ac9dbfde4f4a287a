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
///
/// Exposure (unless CYCLONEDDS_URI is set): by default the participant uses the loopback
/// interface only, with multicast off and unicast discovery of 127.0.0.1, so a pipeline on one
/// host is not discovered from the LAN and advertises no LAN address. Multi-host use opts in by
/// naming interfaces (and peers). Cyclone 0.10 still binds its two unicast receive sockets to
/// 0.0.0.0 (it has no option to bind them to an address): they advertise and answer only on
/// loopback, and deploy/config/cyclonedds.xml is the same configuration for Cyclone's own tools.
#include <string>
#include <vector>

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
    /// Network interfaces by name ("eth0"); empty: loopback only ("lo"), no multicast.
    std::vector<std::string> interfaces;
    /// Unicast discovery peers (addresses or host names). Empty with loopback: 127.0.0.1; empty
    /// with named interfaces: multicast discovery on them. Non-empty: multicast off.
    std::vector<std::string> peers;
    /// Participants one host can hold per domain under unicast discovery (Cyclone's
    /// MaxAutoParticipantIndex + 1; ports 7410 + 2 i for domain 0).
    int max_participants_per_host = 120;
    /// Participant lease, milliseconds: a peer process killed without a goodbye is noticed
    /// (its readers and writers unmatched) this long after its last message. Cyclone sends its
    /// discovery heartbeat every 4/5 of the lease. 0: Cyclone's default (10 s). Ignored when
    /// extra_xml sets <LeaseDuration>.
    int lease_ms = 2000;
    /// Extra Cyclone XML put inside <Domain> (e.g. <Tracing>...).
    std::string extra_xml;
    /// DDS Security: a folder made by deploy/security/make_certs.sh and this participant's
    /// identity in it; empty security_dir: off.
    std::string security_dir;
    std::string security_identity;
    /// Lock file RouDi holds while it runs (iceoryx 2.0).
    std::string roudi_lock_file = "/tmp/roudi.lock";
};

/// True when a RouDi daemon holds its lock file (it is running on this machine).
bool roudi_running(const std::string& lock_file = "/tmp/roudi.lock");

/// Where Debian's libddsc0debian puts Cyclone's security plugins.
constexpr const char* kSecurityPluginDir = "/usr/lib/x86_64-linux-gnu/libddsc0debian";

/// The Cyclone XML the participant uses without CYCLONEDDS_URI (checked names: letters, digits
/// and ".-_:" only, so no XML can be injected through a name).
Result<std::string> domain_xml(const ParticipantConfig& config, bool shared_memory);

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
