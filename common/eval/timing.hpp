#pragma once
/// Per-stage processing times from log files. Services log one line per frame and stage:
///
///   ... timing seq=<frame sequence> stage=<stage> <step>=<ms> [<step>=<ms> ...]
///
/// e.g. "2026-11-24T10:00:00.123 [info] slam: timing seq=12 stage=slam preprocess=3.100
/// tracking=20.500 fusion=8.250 total=31.850": the word "timing" followed by "seq=" starts a
/// record anywhere in a line (after the logger's prefix); values are milliseconds. Other lines
/// are ignored.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/status.hpp"

namespace df::eval {

struct TimingSample {
    int64_t seq = 0;
    std::string stage;
    std::vector<std::pair<std::string, double>> steps_ms;  ///< in the order logged
};

/// "timing seq=12 stage=slam preprocess=3.100 tracking=20.500" (values with 3 decimals). Step
/// and stage names are [A-Za-z0-9_.-]+; `seq` and `stage` are not step names.
std::string format_timing_line(int64_t seq, const std::string& stage,
                               const std::vector<std::pair<std::string, double>>& steps_ms);

/// nullopt for a line without a timing record; kInvalidArgument (what is wrong) for a record
/// that is malformed.
Result<std::optional<TimingSample>> parse_timing_line(const std::string& line);

struct TimingLog {
    std::vector<TimingSample> samples;
    std::vector<std::string> errors;  ///< "<file>:<line>: ..." per malformed record
    size_t lines = 0;
};

/// Reads every timing record of a log file; malformed records are listed, not fatal.
Result<TimingLog> read_timing_log(const std::string& file);

struct TimingStats {
    std::string stage;
    std::string step;
    size_t count = 0;
    double mean_ms = 0;
    double median_ms = 0;
    double p95_ms = 0;  ///< linear interpolation between ranks (numpy.percentile)
    double max_ms = 0;
};

/// Statistics per (stage, step), sorted by stage then by the order steps were first logged.
std::vector<TimingStats> summarize_timing(const std::vector<TimingSample>& samples);

}  // namespace df::eval
