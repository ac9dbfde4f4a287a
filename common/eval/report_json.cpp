// Results as JSON: every figure with its unit in the key name.
#include <fstream>

#include "eval/report.hpp"

namespace df::eval {

using nlohmann::json;

json to_json(const ErrorStats& s) {
    return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
            {"std", s.stddev},  {"min", s.min},   {"max", s.max}};
}

json transform_json(const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q(T.linear());
    json matrix = json::array();
    for (int r = 0; r < 4; ++r) {
        matrix.push_back({T.matrix()(r, 0), T.matrix()(r, 1), T.matrix()(r, 2), T.matrix()(r, 3)});
    }
    return {{"translation_m", {T.translation().x(), T.translation().y(), T.translation().z()}},
            {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}},
            {"rotation_deg", Eigen::AngleAxisd(T.linear()).angle() * kDegPerRad},
            {"matrix", matrix}};
}

json to_json(const AteResult& ate) {
    json alignment = transform_json(ate.gt_T_est);
    alignment["kind"] = to_string(ate.alignment);
    return {{"translation_m", to_json(ate.translation_m)},
            {"pairs", ate.pairs.size()},
            {"gt_poses", ate.gt_poses},
            {"est_poses", ate.est_poses},
            {"association",
             {{"max_difference_s", ate.association.max_difference_s},
              {"offset_s", ate.association.offset_s}}},
            {"alignment_gt_T_est", alignment}};
}

json to_json(const RpeResult& rpe) {
    return {{"delta", rpe.config.delta},
            {"unit", to_string(rpe.config.unit)},
            {"form", to_string(rpe.config.form)},
            {"offset_s", rpe.config.offset_s},
            {"pairs", rpe.pairs.size()},
            {"translation_m", to_json(rpe.translation_m)},
            {"rotation_deg", to_json(rpe.rotation_deg)}};
}

json to_json(const ObjectTrajectoryResult& object) {
    json doc = {{"ate", to_json(object.ate)}, {"rotation_deg", to_json(object.rotation_deg)}};
    if (object.ate.alignment == AlignmentKind::kWorldAndObjectFirstPose) {
        doc["alignment_est_object_T_gt_object"] = transform_json(object.est_object_T_gt_object);
    }
    if (object.rpe) {
        doc["rpe"] = to_json(*object.rpe);
    } else {
        doc["rpe_error"] = object.rpe_error;
    }
    return doc;
}

json to_json(const ReconstructionResult& r) {
    return {{"threshold_m", r.threshold_m},
            {"accuracy", r.accuracy},
            {"completeness", r.completeness},
            {"f_score", r.f_score},
            {"est_points", r.est_points},
            {"gt_points", r.gt_points},
            {"est_to_gt_m", to_json(r.est_to_gt_m)},
            {"gt_to_est_m", to_json(r.gt_to_est_m)}};
}

json to_json(const RegistrationResult& r) {
    const Eigen::Quaterniond q(r.gt_T_est.linear());
    const Eigen::Vector3d t = r.gt_T_est.translation();
    return {{"gt_T_est", {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}},
            {"correction_translation_m", r.correction_translation_m},
            {"correction_rotation_deg", r.correction_rotation_deg},
            {"iterations", r.iterations},
            {"pairs", r.pairs},
            {"pairs_rmse_m", r.rmse_m}};
}

json to_json(const SegmentationResult& seg) {
    json instances = json::array();
    for (const InstanceScore& s : seg.instances) {
        instances.push_back({{"id", s.instance.id},
                             {"name", s.instance.name},
                             {"class_name", s.instance.class_name},
                             {"kind", to_string(s.instance.kind)},
                             {"frames_visible", s.frames_visible},
                             {"frames_matched", s.frames_matched},
                             {"mean_iou", s.mean_iou},
                             {"mean_precision", s.mean_precision},
                             {"mean_recall", s.mean_recall},
                             {"detection_recall", s.detection_recall}});
    }
    json kinds = json::object();
    for (const KindSummary& k : seg.kinds) {
        kinds[k.kind] = {{"instances", k.instances},
                         {"visible", k.visible},
                         {"matched", k.matched},
                         {"mean_iou", k.mean_iou},
                         {"mean_precision", k.mean_precision},
                         {"mean_recall", k.mean_recall},
                         {"detection_recall", k.detection_recall}};
    }
    return {{"match_iou", seg.match_iou},
            {"frames", seg.frames},
            {"frames_without_prediction", seg.frames_without_prediction},
            {"predictions_without_gt", seg.predictions_without_gt},
            {"predicted_segments", seg.predicted_segments},
            {"false_positive_segments", seg.false_positive_segments},
            {"detection_precision", seg.detection_precision},
            {"detection_recall", seg.detection_recall},
            {"kinds", kinds},
            {"instances", instances}};
}

json to_json(const std::vector<TimingStats>& timing) {
    json doc = json::object();
    for (const TimingStats& t : timing) {
        doc[t.stage][t.step] = {{"count", t.count},
                                {"mean_ms", t.mean_ms},
                                {"median_ms", t.median_ms},
                                {"p95_ms", t.p95_ms},
                                {"max_ms", t.max_ms}};
    }
    return doc;
}

namespace {

std::string instance_name(const ObjectMapsResult& r, int gt_id) {
    const GtInstance* inst = r.instance(gt_id);
    return inst ? inst->name : "id " + std::to_string(gt_id);
}

json to_json(const ObjectMapsResult& r, const ObjectTrajectoryResult& t) {
    json doc = {{"translation_m", to_json(t.ate.translation_m)},
                {"rotation_deg", to_json(t.rotation_deg)},
                {"pairs", t.ate.pairs.size()},
                {"gt_poses", t.ate.gt_poses},
                {"est_poses", t.ate.est_poses},
                {"world_alignment", r.world_aligned ? "camera ATE" : "none"},
                {"alignment_gt_T_est", transform_json(t.ate.gt_T_est)},
                {"alignment_est_object_T_gt_object", transform_json(t.est_object_T_gt_object)}};
    if (t.rpe) {
        doc["rpe_1s"] = to_json(*t.rpe);
    } else {
        doc["rpe_error"] = t.rpe_error;
    }
    return doc;
}

}  // namespace

json to_json(const ObjectMapsResult& r) {
    json objects = json::object();
    for (const ObjectMapScore& s : r.objects) {
        json o = {{"gt_id", s.instance.id},
                  {"class_id", s.instance.class_id},
                  {"class_name", s.instance.class_name},
                  {"estimated_id", s.masks.est_id},
                  {"estimated_class_name", s.estimated.class_name},
                  {"mask_iou", s.masks.iou},
                  {"mask_overlap", s.masks.overlap},
                  {"frames", s.masks.frames},
                  {"intersection_px", s.masks.intersection_px},
                  {"estimated_px", s.masks.est_px},
                  {"gt_px", s.masks.gt_px}};
        if (s.trajectory) {
            o["trajectory"] = to_json(r, *s.trajectory);
            o["trajectory"]["gt_file"] = s.gt_trajectory_file;
            o["trajectory"]["est_file"] = s.est_trajectory_file;
        }
        if (s.model) {
            o["model"] = to_json(*s.model);
        } else if (!s.model_note.empty()) {
            o["model_skipped"] = s.model_note;
        }
        if (s.model_registered) {
            o["model_registered"] = to_json(*s.model_registered);
            o["model_registered"]["registration"] = to_json(*s.model_registration);
        } else if (!s.model_registration_note.empty()) {
            o["model_registered_skipped"] = s.model_registration_note;
        }
        objects[s.instance.name] = o;
    }
    json duplicated = json::array(), spurious = json::array(), spurious_why = json::array();
    for (const ObjectPair& d : r.association.duplicates) {
        duplicated.push_back({{"estimated_id", d.est_id},
                              {"of", instance_name(r, d.gt_id)},
                              {"mask_iou", d.iou},
                              {"mask_overlap", d.overlap},
                              {"frames", d.frames}});
    }
    for (const SpuriousObject& s : r.association.spurious) {
        spurious.push_back(s.est_id);
        spurious_why.push_back({{"estimated_id", s.est_id},
                                {"pixels", s.est_px},
                                {"best_gt", s.best_gt_id ? instance_name(r, s.best_gt_id) : ""},
                                {"overlap", s.overlap},
                                {"reason", s.reason}});
    }
    json missed = json::array(), brief = json::array();
    for (int id : r.association.missed) missed.push_back(instance_name(r, id));
    for (int id : r.association.not_expected) brief.push_back(instance_name(r, id));
    const ObjectAssociationConfig& c = r.association.config;
    json association = {{"method", "mask_overlap"},
                        {"min_overlap", c.min_overlap},
                        {"min_frames", c.min_frames},
                        {"frames", r.association.frames},
                        {"frames_without_masks", r.masks.frames_without_masks},
                        {"masks_without_gt", r.masks.masks_without_gt},
                        {"estimated_objects", r.estimated.size()},
                        {"world_alignment", r.world_aligned ? "camera ATE" : "none"},
                        {"spurious", spurious_why},
                        {"rigid_seen_too_briefly", brief}};
    return {{"objects", objects},
            {"objects_duplicated", duplicated},
            {"objects_spurious", spurious},
            {"objects_missed", missed},
            {"objects_not_estimated", missed},
            {"object_association", association}};
}

Status write_json(const std::string& file, const json& doc) {
    std::ofstream out(file, std::ios::trunc);
    out << doc.dump(2) << "\n";
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + file);
    return Status::ok();
}

}  // namespace df::eval
