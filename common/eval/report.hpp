#pragma once
/// Results as terminal tables and as JSON (for scripts).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "eval/object_maps.hpp"
#include "eval/reconstruction.hpp"
#include "eval/segmentation.hpp"
#include "eval/timing.hpp"
#include "eval/trajectory_metrics.hpp"

namespace df::eval {

/// {"translation_m", "quaternion_xyzw", "rotation_deg", "matrix"} (row-major 4x4).
nlohmann::json transform_json(const Eigen::Isometry3d& T);
/// {"count", "rmse", "mean", "median", "std", "min", "max"}
nlohmann::json to_json(const ErrorStats& stats);
/// {"translation_m": stats, "pairs", "gt_poses", "est_poses", "association": {...},
///  "alignment": {"kind", "translation_m", "quaternion_xyzw", "rotation_deg", "matrix"}}
nlohmann::json to_json(const AteResult& ate);
/// {"delta", "unit", "form", "offset_s", "pairs", "translation_m": stats, "rotation_deg": stats}
nlohmann::json to_json(const RpeResult& rpe);
nlohmann::json to_json(const ObjectTrajectoryResult& object);
nlohmann::json to_json(const ReconstructionResult& recon);
nlohmann::json to_json(const RegistrationResult& registration);
nlohmann::json to_json(const SegmentationResult& seg);
nlohmann::json to_json(const std::vector<TimingStats>& timing);
/// The top-level keys of a run's eval.json for object maps: {"objects": {gt name: {...}},
/// "objects_duplicated", "objects_spurious", "objects_missed", "objects_not_estimated" (the same
/// as missed), "object_association"}. See docs/evaluation.md.
nlohmann::json to_json(const ObjectMapsResult& objects);

/// Writes `doc` indented; kIoError naming the file on failure.
Status write_json(const std::string& file, const nlohmann::json& doc);

/// Readable tables, each ending with a newline. `title` heads the table.
std::string format_ate(const AteResult& ate, const std::string& title);
std::string format_rpe(const RpeResult& rpe, const std::string& title);
std::string format_object(const ObjectTrajectoryResult& object, const std::string& title);
std::string format_reconstruction(const ReconstructionResult& recon, const std::string& title);
/// One line: how far the registration moved the reconstruction, its pairs and iterations.
std::string format_registration(const RegistrationResult& registration);
std::string format_segmentation(const SegmentationResult& seg, const std::string& title);
/// One line per rigid instance (and any other matched one), then duplicated / spurious / missed.
std::string format_object_maps(const ObjectMapsResult& objects, const std::string& title);
std::string format_timing(const std::vector<TimingStats>& timing, const std::string& title);

}  // namespace df::eval
