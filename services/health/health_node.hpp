#pragma once
/// df_health: is shared memory still working on this host, and is every stage answering?
///
/// (a) The RouDi probe: every period_s a worker thread creates a fresh writer and reader on a
///     private topic (new iceoryx ports, which need RouDi), writes a loaned sample and must take
///     it back within deadline_s. A cycle that fails or does not finish in time (RouDi stopped
///     or deadlocked blocks the worker inside iceoryx) is a failure; `failures` in a row make
///     RouDi "stuck". The worker never blocks the main thread, which keeps writing the status.
/// (b) Stage answers: every <ns>/stage_status sample refreshes its stage's age.
/// The status is written as JSON to status_path (temp file + rename) every write_period_s;
/// dfsup reads it for `status` and its watcher heals RouDi on "stuck" or a stale file.
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "core/status.hpp"
#include "dds/participant.hpp"

namespace df::health {

struct HealthConfig {
    std::string ns = "df";         ///< topic namespace (<ns>/stage_status)
    std::string status_path;       ///< JSON status file (required)
    double period_s = 1.0;         ///< time between probe cycles, (0.05, 60]
    double deadline_s = 2.0;       ///< a cycle must finish within this, (0.05, 60]
    int failures = 2;              ///< failed cycles in a row that make RouDi stuck, [1, 100]
    double write_period_s = 0.25;  ///< status file rewritten this often, (0.01, 10]
};

/// Checks every field against its range; the message names the flag and the allowed range.
Status validate(const HealthConfig& config);

/// Result of the probe so far (all times steady_ns()).
struct ProbeState {
    uint64_t cycles = 0;           ///< cycles finished
    uint64_t ok = 0;               ///< cycles whose sample came back
    int consecutive_failures = 0;  ///< finished cycles that failed, in a row
    double last_rtt_ms = -1;       ///< write -> take of the last good cycle
    std::string last_error;        ///< why the last failed cycle failed
    bool in_cycle = false;         ///< the worker is inside a cycle now
    int64_t cycle_start_ns = 0;
};

struct StageAnswer {
    uint64_t seq = 0;
    uint64_t epoch = 0;  ///< run epoch of the frame answered (a restarted capture: a new one)
    uint64_t answers = 0;
    int64_t last_ns = 0;          ///< steady_ns() when its last stage_status arrived
    int status = 0;               ///< df::msg FrameStatus of the last answer
    uint64_t writer = 0;          ///< DDS publication handle: a restarted stage has a new one
    int64_t writer_since_ns = 0;  ///< first answer of this writer
    int64_t epoch_since_ns = 0;   ///< first answer of this epoch
};

class HealthNode {
  public:
    HealthNode(const HealthConfig& config, dds::Participant& participant)
        : config_(config), participant_(participant) {}
    ~HealthNode();
    /// Runs until a stop signal. Returns an error when the stage_status reader cannot be made.
    Status run();

  private:
    void probe_loop();
    /// One cycle: fresh endpoints, one sample out and back. Empty string on success.
    std::string probe_once(uint64_t cycle, double* rtt_ms);
    /// Failures in a row, counting a cycle that has run past its deadline (and every further
    /// period it stays stuck) as failed.
    int failures_now(const ProbeState& s, int64_t now_ns) const;
    Status write_status(const std::map<std::string, StageAnswer>& stages, int64_t now_ns);

    HealthConfig config_;
    dds::Participant& participant_;
    std::mutex mutex_;
    ProbeState probe_;
    std::atomic<bool> stop_{false};
    std::thread worker_;
    int64_t started_ns_ = 0;
};

}  // namespace df::health
