// Results as JSON: every figure with its unit in the key name.
#include <fstream>

#include "eval/report.hpp"

namespace df::eval {

using nlohmann::json;

json to_json(const ErrorStats& s) {
    return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
            {"std", s.stddev},  {"min", s.min},   {"max", s.max}};
}

namespace {

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

}  // namespace

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

Status write_json(const std::string& file, const json& doc) {
    std::ofstream out(file, std::ios::trunc);
    out << doc.dump(2) << "\n";
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + file);
    return Status::ok();
}

}  // namespace df::eval
