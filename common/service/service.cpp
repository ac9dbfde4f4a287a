#include "service/service.hpp"

#include <malloc.h>

#include <chrono>
#include <csignal>

#include "config/config_loader.hpp"
#include "config/validate.hpp"
#include "core/log.hpp"

namespace df::service {

void keep_frame_buffers() {
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
}

namespace {
std::atomic<bool> g_stop{false};  // set from signal handlers: the one process-wide flag
extern "C" void on_stop_signal(int) { g_stop.store(true); }
}  // namespace

const std::atomic<bool>& install_stop_handlers() {
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGPIPE, SIG_IGN);
    return g_stop;
}

bool stop_requested() { return g_stop.load(); }

void add_config_flags(CLI::App& app, ConfigFlags* flags) {
    app.add_option("-c,--config", flags->config_path, "configuration file (protobuf text format)");
    app.add_option("--set", flags->overrides,
                   "override a configuration field, text format, e.g. --set 'playback: LOCKSTEP'")
        ->take_all();
}

bool load_config(const ConfigFlags& flags, google::protobuf::Message* config) {
    Status s = config::load(flags.config_path, flags.overrides, config);
    // Every option against the range its .proto declares, before anything is started.
    if (s) s = config::check(*config).with_context("invalid option (" +
                                                   config->GetTypeName() + ")");
    if (!s) {
        log::error(s.message());
        return false;
    }
    log::info("configuration (", config->GetTypeName(), "):\n", config::describe(*config));
    return true;
}

Result<dds::Participant> make_participant(const config::DdsConfig& dds) {
    auto transport = dds::parse_transport(dds.transport());
    if (!transport) return transport.status();
    dds::ParticipantConfig pc;
    pc.domain_id = dds.domain_id();
    pc.transport = *transport;
    pc.extra_xml = dds.extra_xml();
    pc.security_dir = dds.security_dir();
    pc.security_identity = dds.security_identity();
    std::string name;
    for (const char c : dds.interfaces() + ",") {
        if (c == ',' || c == ' ') {
            if (!name.empty()) pc.interfaces.push_back(name);
            name.clear();
        } else {
            name += c;
        }
    }
    pc.peers.assign(dds.peers().begin(), dds.peers().end());
    return dds::Participant::create(pc);
}

int64_t steady_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

}  // namespace df::service
