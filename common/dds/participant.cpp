#include "dds/participant.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
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

bool valid_name(const std::string& name) {
    if (name.empty()) return false;
    for (const char c : name) {
        const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ||
                        c == '_' || c == ':';
        if (!ok) return false;
    }
    return true;
}

}  // namespace

namespace {

/// The <Security> section: Cyclone's authentication, access-control and cryptography plugins
/// with the files of config.security_dir. kInvalidArgument naming the file when one is missing
/// or a name could inject XML.
Result<std::string> security_xml(const ParticipantConfig& config) {
    const std::string& dir = config.security_dir;
    const std::string where = "dds.security_dir '" + dir + "'";
    for (const char c : dir + config.security_identity) {
        if (c == '<' || c == '>' || c == '&' || c == '"' || c == '\'') {
            return Status(StatusCode::kInvalidArgument,
                          where + ": security_dir and security_identity may not contain <>&\"'");
        }
    }
    if (config.security_identity.empty() || !valid_name(config.security_identity)) {
        return Status(StatusCode::kInvalidArgument,
                      where +
                          ": dds.security_identity must name this participant's certificate "
                          "in it (letters, digits and .-_:), e.g. the host's name; got '" +
                          config.security_identity + "'");
    }
    const std::string id = config.security_identity;
    for (const std::string& f : {std::string("identity_ca.pem"), std::string("permissions_ca.pem"),
                                 std::string("governance.p7s"), std::string("permissions.p7s"),
                                 id + ".pem", id + ".key"}) {
        const std::string path = dir + "/" + f;
        if (::access(path.c_str(), R_OK) != 0) {
            return Status(StatusCode::kInvalidArgument,
                          where + ": cannot read '" + path +
                              "' (make the folder with deploy/security/make_certs.sh DIR " + id +
                              " ...)");
        }
    }
    const std::string lib = kSecurityPluginDir;
    const auto file = [&](const std::string& f) { return "file:" + dir + "/" + f; };
    return "<Security><Authentication><Library path=\"" + lib +
           "/libdds_security_auth.so\" initFunction=\"init_authentication\" "
           "finalizeFunction=\"finalize_authentication\"/><IdentityCA>" +
           file("identity_ca.pem") + "</IdentityCA><IdentityCertificate>" + file(id + ".pem") +
           "</IdentityCertificate><PrivateKey>" + file(id + ".key") +
           "</PrivateKey></Authentication><AccessControl><Library path=\"" + lib +
           "/libdds_security_ac.so\" initFunction=\"init_access_control\" "
           "finalizeFunction=\"finalize_access_control\"/><PermissionsCA>" +
           file("permissions_ca.pem") + "</PermissionsCA><Governance>" + file("governance.p7s") +
           "</Governance><Permissions>" + file("permissions.p7s") +
           "</Permissions></AccessControl><Cryptographic><Library path=\"" + lib +
           "/libdds_security_crypto.so\" initFunction=\"init_crypto\" "
           "finalizeFunction=\"finalize_crypto\"/></Cryptographic></Security>";
}

}  // namespace

Result<std::string> domain_xml(const ParticipantConfig& config, bool shared_memory) {
    for (const auto& i : config.interfaces) {
        if (!valid_name(i)) {
            return Status(StatusCode::kInvalidArgument,
                          "dds.interfaces: bad interface name '" + i +
                              "' (expected names like eth0, letters, digits and .-_: only)");
        }
    }
    for (const auto& p : config.peers) {
        if (!valid_name(p)) {
            return Status(StatusCode::kInvalidArgument,
                          "dds.peers: bad peer '" + p +
                              "' (expected an address or host name like 192.0.2.10)");
        }
    }
    if (config.max_participants_per_host < 1 || config.max_participants_per_host > 1000) {
        return Status(StatusCode::kInvalidArgument,
                      "max_participants_per_host " +
                          std::to_string(config.max_participants_per_host) +
                          " out of range [1, 1000]");
    }
    if (config.lease_ms < 0 || config.lease_ms > 3600000) {
        return Status(StatusCode::kInvalidArgument,
                      "participant lease " + std::to_string(config.lease_ms) +
                          " ms out of range [0, 3600000] (0: Cyclone's default, 10 s)");
    }
    const bool loopback = config.interfaces.empty();
    std::vector<std::string> peers = config.peers;
    if (loopback && peers.empty()) peers.push_back("127.0.0.1");
    std::string xml = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>";
    if (loopback) {
        xml += "<NetworkInterface name=\"lo\"/>";
    } else {
        for (const auto& i : config.interfaces) xml += "<NetworkInterface name=\"" + i + "\"/>";
    }
    xml += "</Interfaces>";
    if (!peers.empty()) xml += "<AllowMulticast>false</AllowMulticast>";
    xml += "</General>";
    xml += "<Discovery>";
    // A killed peer is noticed when its lease runs out (Cyclone's default: 10 s); extra_xml
    // that sets its own lease wins.
    if (config.lease_ms > 0 && config.extra_xml.find("LeaseDuration") == std::string::npos) {
        xml += "<LeaseDuration>" + std::to_string(config.lease_ms) + "ms</LeaseDuration>";
    }
    if (!peers.empty()) {
        xml += "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>" +
               std::to_string(config.max_participants_per_host - 1) +
               "</MaxAutoParticipantIndex><Peers>";
        for (const auto& p : peers) xml += "<Peer address=\"" + p + "\"/>";
        xml += "</Peers>";
    }
    xml += "</Discovery>";
    if (shared_memory) {
        xml += "<SharedMemory><Enable>true</Enable><LogLevel>warn</LogLevel></SharedMemory>";
    }
    if (!config.security_dir.empty()) {
        auto security = security_xml(config);
        if (!security) return security.status();
        xml += *security;
    }
    xml += config.extra_xml;
    xml += "</Domain></CycloneDDS>";
    return xml;
}

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
        auto made = domain_xml(config, effective == Transport::kSharedMemory);
        if (!made) return made.status();
        const std::string& xml = *made;
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
    std::string network = "loopback only";
    if (user_uri != nullptr && *user_uri != '\0') {
        network = "as CYCLONEDDS_URI says";
    } else if (!config.interfaces.empty()) {
        network = "interfaces";
        for (const auto& i : config.interfaces) network += " " + i;
    }
    const bool secure = !config.security_dir.empty() && (user_uri == nullptr || *user_uri == '\0');
    log::info("DDS: participant in domain ", config.domain_id, ", transport ", to_string(effective),
              ", network ", network,
              secure ? ", DDS Security as '" + config.security_identity + "' (" +
                           config.security_dir + ")"
                     : std::string());
    return Participant(std::move(domain), Entity(p), effective);
}

}  // namespace df::dds
