// Results as readable terminal tables.
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

std::string transform_line(const Eigen::Isometry3d& T) {
    const Eigen::AngleAxisd aa(T.linear());
    const Eigen::Vector3d& t = T.translation();
    return format(
        "  gt_T_est: t = [%.4f, %.4f, %.4f] m, rotation %.3f deg about [%.3f, %.3f, %.3f]\n", t.x(),
        t.y(), t.z(), aa.angle() * kDegPerRad, aa.axis().x(), aa.axis().y(), aa.axis().z());
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
