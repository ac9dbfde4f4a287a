#pragma once
/// Per-stage timings from a recording: the df::msg::StageStatus messages that every stage
/// publishes on <ns>/stage_status, as `df_tap record` stored them in an MCAP file.
#include <string>
#include <vector>

#include "eval/timing.hpp"

namespace df::eval_cli {

/// Samples of every StageStatus channel of the file (stage name and its timings per frame).
/// Errors name the file; a file without StageStatus channels is an error saying so.
Result<std::vector<eval::TimingSample>> read_timing_recording(const std::string& file);

/// True when the file looks like an MCAP recording (by its magic bytes).
bool is_mcap_file(const std::string& file);

}  // namespace df::eval_cli
