// Relative pose error with a fixed delta, as TUM's evaluate_rpe.py --fixed_delta.
#include <algorithm>
#include <cmath>
#include <set>

#include "eval/trajectory_metrics.hpp"

namespace df::eval {

namespace {

/// Index of the value of a sorted list closest to t; of two equally close, the earlier.
size_t closest_index(const std::vector<double>& sorted, double t) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), t);
    if (it == sorted.begin()) return 0;
    if (it == sorted.end()) return sorted.size() - 1;
    const size_t k = static_cast<size_t>(it - sorted.begin());
    return std::abs(sorted[k] - t) < std::abs(sorted[k - 1] - t) ? k : k - 1;
}

double median_interval(const std::vector<double>& stamps) {
    std::vector<double> diffs;
    for (size_t i = 1; i < stamps.size(); ++i) diffs.push_back(stamps[i] - stamps[i - 1]);
    return summarize_errors(diffs).median;
}

/// TUM's sanity check: estimated stamps that map to a gt stamp and back to themselves or another
/// estimated stamp; fewer than two distinct ones means the files do not overlap in time.
size_t overlapping_stamps(const std::vector<double>& gt, const std::vector<double>& est,
                          double offset_s) {
    std::set<size_t> returned;
    for (double t : est) {
        const double t_gt = gt[closest_index(gt, t + offset_s)];
        returned.insert(closest_index(est, t_gt - offset_s));
    }
    return returned.size();
}

Eigen::Isometry3d relative_error(const Eigen::Isometry3d& est_0, const Eigen::Isometry3d& est_1,
                                 const Eigen::Isometry3d& gt_0, const Eigen::Isometry3d& gt_1,
                                 RpeForm form) {
    const Eigen::Isometry3d est_motion = est_0.inverse() * est_1;  // A
    const Eigen::Isometry3d gt_motion = gt_0.inverse() * gt_1;     // B
    return form == RpeForm::kTumScript ? est_motion * gt_motion.inverse()
                                       : gt_motion.inverse() * est_motion;
}

}  // namespace

Result<RpeResult> compute_rpe(const Trajectory& gt_in, const Trajectory& est_in,
                              const RpeConfig& config) {
    Trajectory gt = gt_in, est = est_in;
    sort_unique_by_stamp(&gt);
    sort_unique_by_stamp(&est);
    if (gt.size() < 2 || est.size() < 2) {
        return error(
            StatusCode::kInvalidArgument,
            "RPE needs at least two poses in each trajectory: " + describe_ranges(gt, est));
    }
    const std::vector<double> gt_stamps = stamps_of(gt), est_stamps = stamps_of(est);
    if (overlapping_stamps(gt_stamps, est_stamps, config.offset_s) < 2) {
        return error(StatusCode::kInvalidArgument,
                     "RPE: the trajectories do not overlap in time: " + describe_ranges(gt, est));
    }
    std::vector<double> index = est_stamps;
    if (config.unit == DeltaUnit::kFrames) {
        for (size_t i = 0; i < index.size(); ++i) index[i] = static_cast<double>(i);
    }
    const double gt_max_difference_s = 2 * median_interval(gt_stamps);

    RpeResult result;
    result.config = config;
    std::vector<double> translations, rotations;
    for (size_t i = 0; i < est.size(); ++i) {
        const size_t j = closest_index(index, index[i] + config.delta);
        if (j == est.size() - 1) continue;  // TUM drops pairs ending at the last pose
        const size_t g0 = closest_index(gt_stamps, est_stamps[i] + config.offset_s);
        const size_t g1 = closest_index(gt_stamps, est_stamps[j] + config.offset_s);
        if (std::abs(gt_stamps[g0] - (est_stamps[i] + config.offset_s)) > gt_max_difference_s ||
            std::abs(gt_stamps[g1] - (est_stamps[j] + config.offset_s)) > gt_max_difference_s) {
            continue;
        }
        const Eigen::Isometry3d e =
            relative_error(to_isometry(est[i]), to_isometry(est[j]), to_isometry(gt[g0]),
                           to_isometry(gt[g1]), config.form);
        RpePair p;
        p.est_stamp_0_s = est_stamps[i];
        p.est_stamp_1_s = est_stamps[j];
        p.gt_stamp_0_s = gt_stamps[g0];
        p.gt_stamp_1_s = gt_stamps[g1];
        p.translation_m = e.translation().norm();
        p.rotation_deg = Eigen::AngleAxisd(e.linear()).angle() * kDegPerRad;
        translations.push_back(p.translation_m);
        rotations.push_back(p.rotation_deg);
        result.pairs.push_back(p);
    }
    if (result.pairs.size() < 2) {
        return error(StatusCode::kInvalidArgument,
                     "RPE: fewer than two pose pairs " + std::to_string(config.delta) + " " +
                         to_string(config.unit) + " apart have ground truth within " +
                         std::to_string(gt_max_difference_s) + " s: " + describe_ranges(gt, est));
    }
    result.translation_m = summarize_errors(translations);
    result.rotation_deg = summarize_errors(rotations);
    return result;
}

}  // namespace df::eval
