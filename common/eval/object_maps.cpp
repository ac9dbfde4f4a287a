// A run's object maps against the sequence's instances: objects.json, association, scoring.
#include "eval/object_maps.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "io/ply/ply.hpp"

namespace df::eval {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// An optional integer field; kInvalidArgument naming `where` if present and not an integer.
template <typename T>
Status read_int(const json& entry, const char* key, const std::string& where, T* value) {
    if (!entry.contains(key) || entry[key].is_null()) return Status::ok();
    if (!entry[key].is_number_integer()) {
        return error(StatusCode::kInvalidArgument, where + "\"" + key + "\" must be an integer");
    }
    *value = entry[key].get<T>();
    return Status::ok();
}

/// An optional string field: a string, null ("") or absent (`fallback`).
Status read_text(const json& entry, const char* key, const std::string& fallback,
                 const std::string& where, std::string* value) {
    if (!entry.contains(key)) {
        *value = fallback;
    } else if (entry[key].is_null()) {
        value->clear();
    } else if (entry[key].is_string()) {
        *value = entry[key].get<std::string>();
    } else {
        return error(StatusCode::kInvalidArgument, where + "\"" + key + "\" must be a string");
    }
    return Status::ok();
}

Result<EstimatedObject> read_entry(const json& e, const std::string& where) {
    if (!e.is_object() || !e.contains("id") || !e["id"].is_number_integer()) {
        return error(StatusCode::kInvalidArgument, where + "expected an integer \"id\"");
    }
    EstimatedObject o;
    o.id = e["id"].get<int>();
    if (o.id < 1 || o.id > 65535) {
        return error(StatusCode::kInvalidArgument,
                     where + "id " + std::to_string(o.id) + " is outside 1..65535");
    }
    const std::string id = std::to_string(o.id);
    DF_RETURN_IF_ERROR(read_int(e, "class_id", where, &o.class_id));
    DF_RETURN_IF_ERROR(read_int(e, "first_frame", where, &o.first_frame));
    DF_RETURN_IF_ERROR(read_int(e, "last_frame", where, &o.last_frame));
    DF_RETURN_IF_ERROR(read_int(e, "frames_tracked", where, &o.frames_tracked));
    DF_RETURN_IF_ERROR(read_int(e, "surfels", where, &o.surfels));
    DF_RETURN_IF_ERROR(read_text(e, "class_name", "", where, &o.class_name));
    DF_RETURN_IF_ERROR(read_text(e, "state", "", where, &o.state));
    DF_RETURN_IF_ERROR(read_text(e, "trajectory", "objects/" + id + ".txt", where, &o.trajectory));
    DF_RETURN_IF_ERROR(read_text(e, "model", "objects/" + id + ".ply", where, &o.model));
    return o;
}

bool file_exists(const fs::path& p) {
    std::error_code ec;
    return fs::exists(p, ec);
}

/// The trajectory of a matched pair with both frames aligned; problems go to result->errors.
void score_trajectory(const fs::path& seq, const fs::path& run,
                      const std::optional<Eigen::Isometry3d>& W, const ObjectMapsConfig& config,
                      const std::string& label, ObjectMapScore* s, ObjectMapsResult* result) {
    if (s->instance.trajectory.empty() || s->estimated.trajectory.empty()) {
        result->errors.push_back(label + ": no trajectory file named (instances.json / " +
                                 (run / "objects.json").string() + ")");
        return;
    }
    s->gt_trajectory_file = (seq / s->instance.trajectory).string();
    s->est_trajectory_file = (run / s->estimated.trajectory).string();
    auto gt = load_trajectory(s->gt_trajectory_file);
    if (!gt) return result->errors.push_back(label + ": " + gt.status().message());
    auto est = load_trajectory(s->est_trajectory_file);
    if (!est) return result->errors.push_back(label + ": " + est.status().message());
    for (const auto* w : {&gt->warnings, &est->warnings}) {
        result->warnings.insert(result->warnings.end(), w->begin(), w->end());
    }
    ObjectAlignment alignment;
    alignment.world_gt_T_est = W;  // absent: identity, since object_frame is set
    alignment.object_frame = true;
    RpeConfig rpe;  // 1 s
    auto errors = compute_object_errors(gt->poses, est->poses, alignment, config.stamps, rpe);
    if (!errors) {
        result->errors.push_back(label + ": " + s->est_trajectory_file + " against " +
                                 s->gt_trajectory_file + ": " + errors.status().message());
        return;
    }
    s->trajectory = std::move(*errors);
    s->gt_poses = std::move(gt->poses);
    s->est_poses = std::move(est->poses);
}

/// The estimated model moved into the ground-truth object frame (p_gt = X^-1 p_est).
void score_model(const fs::path& seq, const fs::path& run, const ObjectMapsConfig& config,
                 const std::string& label, ObjectMapScore* s, ObjectMapsResult* result) {
    if (s->estimated.model.empty()) {
        s->model_note = "objects.json names no model";
        return;
    }
    const fs::path est_file = run / s->estimated.model;
    if (!file_exists(est_file)) {
        s->model_note = "no " + est_file.string();
        return;
    }
    if (s->instance.model.empty()) {
        s->model_note = "the ground truth has no model";
        return;
    }
    if (!s->trajectory) {
        s->model_note = "no trajectory, so no object frame alignment";
        return;
    }
    const fs::path gt_file = seq / s->instance.model;
    auto gt = io::read_ply(gt_file.string());
    if (!gt) return result->errors.push_back(label + ": " + gt.status().message());
    auto est = io::read_ply(est_file.string());
    if (!est) return result->errors.push_back(label + ": " + est.status().message());
    const Eigen::Isometry3d gt_T_est_object = s->trajectory->est_object_T_gt_object.inverse();
    auto recon = score_reconstruction(
        gt->positions, transform_points(gt_T_est_object, est->positions), config.model);
    if (!recon) {
        result->errors.push_back(label + ": " + est_file.string() + " against " + gt_file.string() +
                                 ": " + recon.status().message());
        return;
    }
    s->model = std::move(*recon);
    auto registered = score_registered(gt->positions, est->positions, gt_T_est_object,
                                       config.model, config.model_registration);
    if (!registered) {
        s->model_registration_note = registered.status().message();
        return;
    }
    s->model_registration = registered->registration;
    s->model_registered = registered->score;
}

}  // namespace

Result<std::vector<EstimatedObject>> read_objects_json(const std::string& file) {
    std::ifstream in(file);
    if (!in) return error(StatusCode::kNotFound, file + ": cannot open objects file");
    json doc;
    try {
        doc = json::parse(in);
    } catch (const json::exception& e) {
        return error(StatusCode::kInvalidArgument, file + ": not valid JSON: " + e.what());
    }
    if (!doc.is_object() || !doc.contains("objects") || !doc["objects"].is_array()) {
        return error(StatusCode::kInvalidArgument,
                     file + ": expected an object with an array \"objects\"");
    }
    std::vector<EstimatedObject> objects;
    std::set<int> ids;
    for (size_t i = 0; i < doc["objects"].size(); ++i) {
        const std::string where = file + ": objects[" + std::to_string(i) + "]: ";
        auto entry = read_entry(doc["objects"][i], where);
        if (!entry) return entry.status();
        if (!ids.insert(entry->id).second) {
            return error(StatusCode::kInvalidArgument,
                         where + "id " + std::to_string(entry->id) + " is listed twice");
        }
        objects.push_back(std::move(*entry));
    }
    return objects;
}

const GtInstance* ObjectMapsResult::instance(int gt_id) const {
    for (const GtInstance& inst : masks.instances) {
        if (inst.id == gt_id) return &inst;
    }
    return nullptr;
}

Result<ObjectMapsResult> score_object_maps(const std::string& sequence_dir,
                                           const std::string& run_dir,
                                           const std::optional<Eigen::Isometry3d>& world_gt_T_est,
                                           const ObjectMapsConfig& config) {
    const fs::path seq(sequence_dir), run(run_dir);
    ObjectMapsResult result;
    auto estimated = read_objects_json((run / "objects.json").string());
    if (!estimated) return estimated.status();
    result.estimated = std::move(*estimated);
    auto masks = accumulate_mask_folders(sequence_dir, run_dir);
    if (!masks) return masks.status();
    result.masks = std::move(*masks);
    result.world_aligned = world_gt_T_est.has_value();
    result.model_threshold_m = config.model.threshold_m;

    std::vector<int> listed;
    for (const EstimatedObject& o : result.estimated) listed.push_back(o.id);
    for (const auto& e : result.masks.overlap.estimated()) {
        if (std::find(listed.begin(), listed.end(), e.first) == listed.end()) {
            result.errors.push_back((run / "object_masks").string() + ": object id " +
                                    std::to_string(e.first) + " claims " +
                                    std::to_string(e.second.pixels) + " pixels but " +
                                    (run / "objects.json").string() + " does not list it");
        }
    }
    result.association =
        associate_objects(result.masks.overlap, result.masks.instances, listed, config.association);
    for (const ObjectPair& match : result.association.matches) {
        ObjectMapScore s;
        s.instance = *result.instance(match.gt_id);
        s.masks = match;
        s.estimated.id = match.est_id;
        s.estimated.trajectory.clear();  // an unlisted object has no files
        s.estimated.model.clear();
        for (const EstimatedObject& o : result.estimated) {
            if (o.id == match.est_id) s.estimated = o;
        }
        const std::string label =
            "object " + s.instance.name + " (estimated " + std::to_string(match.est_id) + ")";
        score_trajectory(seq, run, world_gt_T_est, config, label, &s, &result);
        score_model(seq, run, config, label, &s, &result);
        result.objects.push_back(std::move(s));
    }
    return result;
}

}  // namespace df::eval
