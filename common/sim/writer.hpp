#pragma once
/// Renders a Sequence and writes its folder (docs/sequence_format.md): rgb/, depth/,
/// instances/, rgb.txt, depth.txt, associations.txt, groundtruth.txt, intrinsics.txt,
/// instances.json, objects/<name>.txt, models/<name>.ply, models/static.ply, sequence.json.
#include <functional>
#include <string>

#include "core/status.hpp"
#include "sim/sequence.hpp"

namespace df::sim {

struct WriteOptions {
    int threads = 0;     ///< <= 0: all hardware threads; the output does not depend on it
    bool models = true;  ///< write models/*.ply
    /// Called after each frame with (frames done, frames in all); may be empty.
    std::function<void(int, int)> progress;
};

struct WriteReport {
    double frames_s = 0;  ///< rendering, sensor model, PNG encoding and writing of all frames
    double models_s = 0;  ///< model sampling and PLY writing
};

/// Writes the sequence into `folder`. The folder must be new, empty, or an earlier output of
/// this generator (it has sequence.json): then its generated files are replaced and nothing else
/// is touched. Errors name the file that failed.
Result<WriteReport> write_sequence(const Sequence& sequence, const std::string& folder,
                                   const WriteOptions& options = {});

/// sequence.json's text (preset, seed, sizes, intrinsics, sensor settings, generator version).
std::string sequence_json(const Sequence& sequence);
/// instances.json's text.
std::string instances_json(const Sequence& sequence);

}  // namespace df::sim
