#pragma once
/// What every service main() shares: stop on SIGINT/SIGTERM, the --config/--set flags, and a
/// DDS participant made from the DdsConfig part of the service's configuration.
#include <google/protobuf/message.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "dds.pb.h"
#include "dds/participant.hpp"

namespace df::service {

/// Installs SIGINT/SIGTERM handlers that set the returned flag (SIGPIPE ignored).
const std::atomic<bool>& install_stop_handlers();
bool stop_requested();

struct ConfigFlags {
    std::string config_path;
    std::vector<std::string> overrides;
};

/// Adds --config FILE and --set 'field: value' (repeatable) to an app.
void add_config_flags(CLI::App& app, ConfigFlags* flags);

/// Loads the configuration (file, then overrides) and logs every effective value.
/// On error logs it and returns false.
bool load_config(const ConfigFlags& flags, google::protobuf::Message* config);

/// Creates the participant the DdsConfig describes.
Result<dds::Participant> make_participant(const config::DdsConfig& dds);

/// Monotonic clock, nanoseconds (for timing and deadlines; not comparable across processes).
int64_t steady_ns();

/// The common tail of a service's main(): makes the participant from `dds`, the node with
/// `create(participant)` (a Result<std::unique_ptr<Node>>), runs it; logs any error. Returns the
/// process exit code: 0, or 1 on failure.
template <typename Create>
int run_node(const config::DdsConfig& dds, Create&& create) {
    auto participant = make_participant(dds);
    if (!participant) {
        log::error(participant.status().message());
        return 1;
    }
    auto node = create(*participant);
    if (!node) {
        log::error(node.status().message());
        return 1;
    }
    if (auto s = (*node)->run(); !s) {
        log::error(s.message());
        return 1;
    }
    return 0;
}

}  // namespace df::service
