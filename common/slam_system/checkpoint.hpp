#pragma once
/// SLAM checkpoints: a SystemState plus where in the stream it was taken, in one binary file
/// written atomically (temporary file, fsync, rename), so a crash at any moment leaves either
/// the previous checkpoint or the new one, never a mix.
///
/// Format (little-endian): "DFSLAMCK" magic, u32 version, u64 payload length, the payload, then
/// a u64 FNV-1a hash of the payload. Payload: last seq, epoch and sensor stamp (ns) of the
/// frame last handled; frames, lost frames, map time, started, lost, input size; world_T_camera
/// and last_motion (12 doubles each, rotation row-major then translation); the trajectory
/// (count, then stamp_s, t, q x y z w as doubles); the surfels (count, rejected-by-capacity
/// count, then per surfel position, normal, colour, radius, confidence as floats and init and
/// last-seen frames as i32). Version 2 (written now) goes on with the object maps: next id, the
/// five counters, the count, then per map id, class, score, retired, first / last-seen frame,
/// frames tracked, frames lost, world_T_object, body motion, its trajectory and its surfels (in
/// the object's frame) as above. Version 1 files (no object maps) are still read.
#include <cstdint>
#include <string>

#include "core/status.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam {

struct Checkpoint {
    SystemState system;
    uint64_t last_seq = 0;       ///< header.seq of the last frame handled
    uint64_t last_epoch = 0;     ///< its capture run epoch
    int64_t last_sensor_ns = 0;  ///< its sensor stamp
};

/// Writes `checkpoint` to `file` atomically (via "<file>.tmp"). kIoError naming the file.
Status write_checkpoint(const std::string& file, const Checkpoint& checkpoint);

/// Reads a checkpoint. kNotFound when the file does not exist; kIoError naming the file and
/// what is wrong (not a checkpoint, other version, truncated at byte N of M, hash mismatch,
/// impossible counts) otherwise.
Result<Checkpoint> read_checkpoint(const std::string& file);

}  // namespace df::slam
