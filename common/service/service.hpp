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

/// Keeps freed frame-sized buffers (up to 32 MiB) in the heap for the next frame instead of
/// handing them back to the kernel. glibc maps every allocation over its mmap threshold afresh,
/// and the page faults of touching a new 640x480 buffer on every frame cost more than the work
/// on it (df_geoseg at 30 Hz: 77 -> 23 ms of CPU per frame; docs/realtime.md, "Where the CPU
/// goes"). The heap then stays at its peak size. Called once by every service's main().
void keep_frame_buffers();

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

/// When a service's input stream has ended: its writers came and went with nothing left to
/// handle, or (idle_exit_s > 0) no input arrived for that long after the first. With
/// writers_grace_s > 0 the writers must stay gone that long (a supervisor restarts a killed
/// writer within it, and the stream goes on).
class StreamEnd {
  public:
    explicit StreamEnd(double idle_exit_s, double writers_grace_s = 0)
        : idle_exit_s_(idle_exit_s), writers_grace_s_(writers_grace_s) {}
    /// An input arrived.
    void on_input() {
        started_ = true;
        last_ns_ = steady_ns();
    }
    /// After each wake-up: `writers` now matched, `drained` true when nothing waits. Returns
    /// why the stream ended ("the frame writers left", "no frame for idle_exit_s") or nullptr.
    const char* check(uint32_t writers, bool drained) {
        if (writers > 0) {
            had_writers_ = true;
            gone_since_ns_ = 0;
        }
        if (!started_) return nullptr;
        if (had_writers_ && writers == 0 && drained) {
            if (gone_since_ns_ == 0) gone_since_ns_ = steady_ns();
            const double gone_s = static_cast<double>(steady_ns() - gone_since_ns_) * 1e-9;
            if (gone_s >= writers_grace_s_) return "the frame writers left";
        }
        if (idle_exit_s_ > 0 && static_cast<double>(steady_ns() - last_ns_) * 1e-9 > idle_exit_s_) {
            return "no frame for idle_exit_s";
        }
        return nullptr;
    }
    /// Ready for the next stream.
    void reset() {
        had_writers_ = started_ = false;
        gone_since_ns_ = 0;
    }

  private:
    double idle_exit_s_;
    double writers_grace_s_;
    bool had_writers_ = false, started_ = false;
    int64_t gone_since_ns_ = 0;  // steady_ns() when the writers were first seen gone
    int64_t last_ns_ = 0;
};

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
