#include "eval/plots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

#include "eval/plot_canvas.hpp"

namespace df::eval {

namespace {

const cv::Size kPanel(720, 560);
const char* const kAxisNames[] = {"x", "y", "z"};

const cv::Point2d kBreak(std::numeric_limits<double>::quiet_NaN(), 0.0);

/// Twice the median interval of sorted stamps: a longer step is a gap, where lines break (as in
/// TUM's plots).
double gap_threshold(const std::vector<double>& stamps) {
    std::vector<double> steps;
    for (size_t i = 1; i < stamps.size(); ++i) steps.push_back(stamps[i] - stamps[i - 1]);
    if (steps.empty()) return 0;
    std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2),
                     steps.end());
    return 2 * steps[steps.size() / 2];
}

/// Positions on two axes, broken at gaps.
std::vector<cv::Point2d> top_view(const Trajectory& t, const Eigen::Isometry3d& T, int a, int b) {
    const double gap = gap_threshold(stamps_of(t));
    std::vector<cv::Point2d> points;
    for (size_t i = 0; i < t.size(); ++i) {
        if (i > 0 && t[i].stamp_s - t[i - 1].stamp_s > gap) points.push_back(kBreak);
        const Eigen::Vector3d p = T * t[i].t;
        points.emplace_back(p[a], p[b]);
    }
    return points;
}

}  // namespace

std::pair<int, int> widest_axes(const Trajectory& trajectory) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (const auto& p : trajectory) {
        lo = lo.cwiseMin(p.t);
        hi = hi.cwiseMax(p.t);
    }
    const Eigen::Vector3d extent = hi - lo;
    int narrowest = 0;
    for (int k = 1; k < 3; ++k) {
        if (extent[k] < extent[narrowest]) narrowest = k;
    }
    const int a = narrowest == 0 ? 1 : 0;
    const int b = narrowest == 2 ? 1 : 2;
    return {a, b};
}

Status plot_ate(const std::string& file, const AteResult& ate, const Trajectory& gt,
                const Trajectory& est, const std::string& title) {
    const auto [a, b] = widest_axes(gt);
    PlotPanel view;
    view.title = title + ": top view";
    view.x_label = std::string(kAxisNames[a]) + " [m]";
    view.y_label = std::string(kAxisNames[b]) + " [m]";
    view.equal_aspect = true;
    PlotSegments residuals{{}, colors::kDifference, "difference", 1};
    for (const AtePair& p : ate.pairs) {
        residuals.lines.emplace_back(
            cv::Point2d(p.gt_position[a], p.gt_position[b]),
            cv::Point2d(p.est_position_aligned[a], p.est_position_aligned[b]));
    }
    view.segments.push_back(residuals);
    view.series.push_back({top_view(gt, Eigen::Isometry3d::Identity(), a, b), colors::kGroundTruth,
                           "ground truth", 2});
    view.series.push_back({top_view(est, ate.gt_T_est, a, b), colors::kEstimate,
                           ate.alignment == AlignmentKind::kHornPositions
                               ? "estimate, aligned (Horn)"
                               : "estimate, first pose aligned",
                           2});

    PlotPanel errors;
    char text[160];
    std::snprintf(text, sizeof text, "position error: RMSE %.4f m, max %.4f m (%zu pairs)",
                  ate.translation_m.rmse, ate.translation_m.max, ate.translation_m.count);
    errors.title = text;
    errors.x_label = "time since first pair [s]";
    errors.y_label = "position error [m]";
    errors.y_from_zero = true;
    PlotSeries series{{}, colors::kDifference, "", 2};
    const double t0 = ate.pairs.empty() ? 0 : ate.pairs.front().gt_stamp_s;
    std::vector<double> pair_stamps;
    for (const AtePair& p : ate.pairs) pair_stamps.push_back(p.gt_stamp_s);
    const double gap = gap_threshold(pair_stamps);
    for (size_t i = 0; i < ate.pairs.size(); ++i) {
        if (i > 0 && pair_stamps[i] - pair_stamps[i - 1] > gap) series.points.push_back(kBreak);
        series.points.emplace_back(pair_stamps[i] - t0, ate.pairs[i].error_m);
    }
    errors.series.push_back(series);
    PlotSeries rmse{
        {{0, ate.translation_m.rmse},
         {ate.pairs.empty() ? 1 : ate.pairs.back().gt_stamp_s - t0, ate.translation_m.rmse}},
        colors::kSecond,
        "RMSE",
        1};
    errors.series.push_back(rmse);

    cv::Mat image;
    cv::hconcat(render_panel(view, kPanel), render_panel(errors, kPanel), image);
    return write_png(file, image);
}

Status plot_object(const std::string& file, const ObjectTrajectoryResult& object,
                   const Trajectory& gt, const Trajectory& est, const std::string& title) {
    AteResult moved = object.ate;  // the poses below are already aligned
    moved.gt_T_est = Eigen::Isometry3d::Identity();
    return plot_ate(file, moved, gt, aligned_object_poses(object, est), title);
}

Status plot_rpe(const std::string& file, const RpeResult& rpe, const std::string& title) {
    const double t0 = rpe.pairs.empty() ? 0 : rpe.pairs.front().est_stamp_0_s;
    char delta[64];
    std::snprintf(delta, sizeof delta, "%g %s", rpe.config.delta,
                  rpe.config.unit == DeltaUnit::kSeconds ? "s" : "frame(s)");
    PlotPanel trans, rot;
    char text[160];
    std::snprintf(text, sizeof text, "%s: translation over %s (RMSE %.4f m)", title.c_str(), delta,
                  rpe.translation_m.rmse);
    trans.title = text;
    std::snprintf(text, sizeof text, "rotation over %s (RMSE %.3f deg)", delta,
                  rpe.rotation_deg.rmse);
    rot.title = text;
    trans.x_label = rot.x_label = "time of the first pose of the pair [s]";
    trans.y_label = "translational error [m]";
    rot.y_label = "rotational error [deg]";
    trans.y_from_zero = rot.y_from_zero = true;
    PlotSeries ts{{}, colors::kEstimate, "", 2}, rs{{}, colors::kDifference, "", 2};
    std::vector<double> starts;
    for (const RpePair& p : rpe.pairs) starts.push_back(p.est_stamp_0_s);
    const double gap = gap_threshold(starts);
    for (size_t i = 0; i < rpe.pairs.size(); ++i) {
        if (i > 0 && starts[i] - starts[i - 1] > gap) {
            ts.points.push_back(kBreak);
            rs.points.push_back(kBreak);
        }
        ts.points.emplace_back(starts[i] - t0, rpe.pairs[i].translation_m);
        rs.points.emplace_back(starts[i] - t0, rpe.pairs[i].rotation_deg);
    }
    trans.series.push_back(ts);
    rot.series.push_back(rs);
    cv::Mat image;
    cv::hconcat(render_panel(trans, kPanel), render_panel(rot, kPanel), image);
    return write_png(file, image);
}

}  // namespace df::eval
