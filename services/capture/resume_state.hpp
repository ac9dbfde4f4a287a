#pragma once
/// Restarts that resume: capture's record of the last frame that is done (published and, in
/// lockstep, answered by every stage it waited for), so that a capture restarted after a crash
/// goes on after that frame instead of playing its source from frame 0.
///
/// The file is text, one "key value" per line ('#' comments), written to "<file>.tmp" and
/// renamed over the file, so a reader sees the old record or the new one, never half of one:
///   folder <path>  ns <namespace>  source_id <n>   what the record is for
///   loop <n>            the loop (0-based) the frame belongs to
///   last_sensor_ns <n>  its stamp (the rgb stamp of the TUM list, ns)
///   frames_done <n>     frames done in all runs so far (max_frames counts them)
///   finished <0|1>      1: the source was played to its end (nothing left to resume)
#include <cstdint>
#include <optional>
#include <string>

#include "core/status.hpp"

namespace df::capture {

struct ResumeState {
    std::string folder;
    std::string ns;
    uint32_t source_id = 0;
    uint32_t loop = 0;
    int64_t last_sensor_ns = -1;  ///< -1: no frame done yet
    uint64_t frames_done = 0;
    bool finished = false;
};

/// The record in `path`; nullopt when there is no such file. kInvalidArgument naming the file,
/// the line and the field for a malformed record; kIoError when it cannot be read.
Result<std::optional<ResumeState>> read_resume_state(const std::string& path);

/// Writes the record atomically (creating the file's folder); kIoError naming the file.
Status write_resume_state(const std::string& path, const ResumeState& state);

/// Why `saved` is not a record of the source `current` describes (folder, ns, source id), or ""
/// when it is.
std::string resume_mismatch(const ResumeState& saved, const ResumeState& current);

}  // namespace df::capture
