// Results as readable terminal tables.
#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "eval/report.hpp"

namespace df::eval {

namespace {

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
    char text[1024];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    return text;
}

const char* const kStatsHeader = "  %-22s %10s %10s %10s %10s %10s %10s  %s\n";

std::string stats_header() {
    return format(kStatsHeader, "", "rmse", "mean", "median", "std", "min", "max", "");
}

std::string stats_row(const std::string& name, const ErrorStats& s, const char* unit,
                      int decimals) {
    return format("  %-22s %10.*f %10.*f %10.*f %10.*f %10.*f %10.*f  %s\n", name.c_str(), decimals,
                  s.rmse, decimals, s.mean, decimals, s.median, decimals, s.stddev, decimals, s.min,
                  decimals, s.max, unit);
}

std::string transform_line(const Eigen::Isometry3d& T, const char* name = "gt_T_est") {
    const Eigen::AngleAxisd aa(T.linear());
    const Eigen::Vector3d& t = T.translation();
    return format("  %s: t = [%.4f, %.4f, %.4f] m, rotation %.3f deg about [%.3f, %.3f, %.3f]\n",
                  name, t.x(), t.y(), t.z(), aa.angle() * kDegPerRad, aa.axis().x(), aa.axis().y(),
                  aa.axis().z());
}

}  // namespace

std::string format_ate(const AteResult& ate, const std::string& title) {
    std::string s = title + "\n";
    s += format(
        "  %zu pairs (ground truth %zu poses, estimate %zu poses; |dt| < %g s, offset %g s), "
        "alignment %s\n",
        ate.pairs.size(), ate.gt_poses, ate.est_poses, ate.association.max_difference_s,
        ate.association.offset_s, to_string(ate.alignment));
    s += stats_header();
    s += stats_row("ATE translation", ate.translation_m, "m", 4);
    s += transform_line(ate.gt_T_est);
    return s;
}

std::string format_rpe(const RpeResult& rpe, const std::string& title) {
    std::string s = title + "\n";
    s += format("  %zu pairs %g %s apart (%s form)\n", rpe.pairs.size(), rpe.config.delta,
                rpe.config.unit == DeltaUnit::kSeconds ? "s" : "frame(s)",
                to_string(rpe.config.form));
    s += stats_header();
    s += stats_row("RPE translation", rpe.translation_m, "m", 4);
    s += stats_row("RPE rotation", rpe.rotation_deg, "deg", 3);
    return s;
}

std::string format_object(const ObjectTrajectoryResult& object, const std::string& title) {
    std::string s = format_ate(object.ate, title);
    if (object.ate.alignment == AlignmentKind::kWorldAndObjectFirstPose) {
        s += transform_line(object.est_object_T_gt_object, "est_object_T_gt_object");
    }
    s += stats_row("rotation (aligned)", object.rotation_deg, "deg", 3);
    if (object.rpe) {
        s += format("  RPE over %g %s, %zu pairs:\n", object.rpe->config.delta,
                    to_string(object.rpe->config.unit), object.rpe->pairs.size());
        s += stats_row("RPE translation", object.rpe->translation_m, "m", 4);
        s += stats_row("RPE rotation", object.rpe->rotation_deg, "deg", 3);
    } else {
        s += "  RPE not computed: " + object.rpe_error + "\n";
    }
    return s;
}

std::string format_reconstruction(const ReconstructionResult& r, const std::string& title) {
    std::string s = title + "\n";
    s += format("  threshold %.4f m; reconstruction %zu points, ground truth %zu points\n",
                r.threshold_m, r.est_points, r.gt_points);
    s += format("  accuracy     %.4f  (reconstructed points within threshold of the model)\n",
                r.accuracy);
    s += format("  completeness %.4f  (model points within threshold of the reconstruction)\n",
                r.completeness);
    s += format("  F-score      %.4f\n", r.f_score);
    s += stats_header();
    s += stats_row("reconstruction->model", r.est_to_gt_m, "m", 4);
    s += stats_row("model->reconstruction", r.gt_to_est_m, "m", 4);
    return s;
}

std::string format_segmentation(const SegmentationResult& seg, const std::string& title) {
    std::string s = title + "\n";
    s += format(
        "  %zu frames scored; %zu ground-truth frames had no prediction, %zu predictions "
        "no ground truth; a match needs IoU >= %.2f\n",
        seg.frames, seg.frames_without_prediction, seg.predictions_without_gt, seg.match_iou);
    s += format("  detection precision %.4f (%zu of %zu predicted segments matched), recall %.4f\n",
                seg.detection_precision, seg.predicted_segments - seg.false_positive_segments,
                seg.predicted_segments, seg.detection_recall);
    s += format("  %-5s %-20s %-10s %8s %8s %9s %9s %9s\n", "id", "name", "kind", "visible",
                "matched", "mean IoU", "mask prec", "mask rec");
    for (const InstanceScore& i : seg.instances) {
        s += format("  %-5d %-20s %-10s %8zu %8zu %9.4f %9.4f %9.4f\n", i.instance.id,
                    i.instance.name.c_str(), to_string(i.instance.kind), i.frames_visible,
                    i.frames_matched, i.mean_iou, i.mean_precision, i.mean_recall);
    }
    s += format("  %-26s %9s %8s %8s %9s %9s %9s %9s\n", "by kind", "instances", "visible",
                "matched", "recall", "mean IoU", "mask prec", "mask rec");
    for (const KindSummary& k : seg.kinds) {
        s += format("  %-26s %9zu %8zu %8zu %9.4f %9.4f %9.4f %9.4f\n", k.kind.c_str(), k.instances,
                    k.visible, k.matched, k.detection_recall, k.mean_iou, k.mean_precision,
                    k.mean_recall);
    }
    return s;
}

namespace {

const char* const kObjectColumns = "  %-16s %-10s %6s %9s %7s %10s %9s %10s %10s\n";

/// One table line of a ground-truth instance and the object matched to it.
std::string object_line(const ObjectMapScore& o) {
    std::string t_rmse = "-", r_rmse = "-", acc = "-", compl_ = "-";
    if (o.trajectory) {
        t_rmse = format("%.2f", 100 * o.trajectory->ate.translation_m.rmse);
        r_rmse = format("%.2f", o.trajectory->rotation_deg.rmse);
    }
    if (o.model) {
        acc = format("%.4f", o.model->accuracy);
        compl_ = format("%.4f", o.model->completeness);
    }
    return format("  %-16s %-10s %6d %9.4f %7zu %10s %9s %10s %10s\n", o.instance.name.c_str(),
                  o.instance.class_name.c_str(), o.masks.est_id, o.masks.iou, o.masks.frames,
                  t_rmse.c_str(), r_rmse.c_str(), acc.c_str(), compl_.c_str());
}

std::string name_of(const ObjectMapsResult& r, int gt_id) {
    const GtInstance* inst = r.instance(gt_id);
    return inst ? inst->name : "id " + std::to_string(gt_id);
}

/// "label: a, b" or "label: none".
std::string list_line(const std::string& label, const std::vector<std::string>& items) {
    std::string s = "  " + label + ":";
    for (size_t i = 0; i < items.size(); ++i) s += (i ? ", " : " ") + items[i];
    return s + (items.empty() ? " none\n" : "\n");
}

}  // namespace

std::string format_object_maps(const ObjectMapsResult& r, const std::string& title) {
    const ObjectAssociation& a = r.association;
    std::string s = title + "\n";
    s += format(
        "  %zu estimated objects, associated by mask overlap over %zu frames (%zu not processed "
        "by the run):\n  a match needs %.0f%% of an object's pixels on a rigid "
        "instance; world alignment: %s\n",
        r.estimated.size(), a.frames, r.masks.frames_without_masks, 100 * a.config.min_overlap,
        r.world_aligned ? "camera ATE" : "none");
    const std::string at = format("@%.1f cm", 100 * r.model_threshold_m);
    s += format(kObjectColumns, "gt object", "class", "est id", "mask IoU", "frames", "traj RMSE",
                "rot RMSE", "model acc", "complete");
    s += format(kObjectColumns, "", "", "", "", "", "[cm]", "[deg]", at.c_str(), at.c_str());
    for (const GtInstance& inst : r.masks.instances) {
        const auto o =
            std::find_if(r.objects.begin(), r.objects.end(),
                         [&](const ObjectMapScore& x) { return x.instance.id == inst.id; });
        if (o != r.objects.end()) {
            s += object_line(*o);
        } else if (inst.kind == InstanceKind::kRigid) {
            const auto g = r.masks.overlap.ground_truth().find(inst.id);
            const size_t frames = g == r.masks.overlap.ground_truth().end() ? 0 : g->second.frames;
            s += format("  %-16s %-10s %6s   (no object; visible in %zu frames)\n",
                        inst.name.c_str(), inst.class_name.c_str(), "-", frames);
        }
    }
    std::vector<std::string> items;
    for (const ObjectPair& d : a.duplicates) {
        items.push_back(format("%d of %s (mask IoU %.3f, %zu frames)", d.est_id,
                               name_of(r, d.gt_id).c_str(), d.iou, d.frames));
    }
    for (const ObjectMapScore& o : r.objects) {
        if (o.model_registered) {
            s += format("  %s model after rigid registration onto the ground truth (%s): "
                        "acc %.4f, complete %.4f %s\n",
                        o.instance.name.c_str(),
                        format_registration(*o.model_registration).c_str(),
                        o.model_registered->accuracy, o.model_registered->completeness,
                        at.c_str());
        } else if (!o.model_registration_note.empty()) {
            s += format("  %s model not registered: %s\n", o.instance.name.c_str(),
                        o.model_registration_note.c_str());
        }
    }
    s += list_line("duplicated", items);
    items.clear();
    for (const SpuriousObject& sp : a.spurious) {
        items.push_back(format("%d (%s)", sp.est_id, sp.reason.c_str()));
    }
    s += list_line("spurious", items);
    items.clear();
    for (int id : a.missed) items.push_back(name_of(r, id));
    s += list_line("missed", items);
    return s;
}

std::string format_registration(const RegistrationResult& r) {
    return format("moved %.2f cm, %.2f deg; %zu pairs at %.2f cm RMS, %d iterations",
                  100 * r.correction_translation_m, r.correction_rotation_deg, r.pairs,
                  100 * r.rmse_m, r.iterations);
}

std::string format_timing(const std::vector<TimingStats>& timing, const std::string& title) {
    std::string s = title + "\n";
    s += format("  %-14s %-18s %7s %10s %10s %10s %10s\n", "stage", "step", "count", "mean",
                "median", "p95", "max");
    for (const TimingStats& t : timing) {
        s += format("  %-14s %-18s %7zu %10.3f %10.3f %10.3f %10.3f  ms\n", t.stage.c_str(),
                    t.step.c_str(), t.count, t.mean_ms, t.median_ms, t.p95_ms, t.max_ms);
    }
    if (timing.empty()) s += "  (no timing records)\n";
    return s;
}

}  // namespace df::eval
