#pragma once
/// What every service main() shares: stop on SIGINT/SIGTERM, the --config/--set flags, and a
/// DDS participant made from the DdsConfig part of the service's configuration.
#include <google/protobuf/message.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <string>
#include <vector>

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

}  // namespace df::service
