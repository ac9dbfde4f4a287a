#pragma once
/// The evaluation figures as PNG files (OpenCV drawing).
#include <string>

#include "core/status.hpp"
#include "eval/trajectory_metrics.hpp"

namespace df::eval {

/// Left: top view of the ground truth and the aligned estimate (every pose, lines broken at gaps
/// longer than twice the median interval) with the residual of each associated pair, on the two
/// world axes along which the ground truth extends most; right: position error over time.
/// Works for camera ATE (Horn) and object trajectories (first-pose alignment) alike.
Status plot_ate(const std::string& file, const AteResult& ate, const Trajectory& gt,
                const Trajectory& est, const std::string& title);

/// plot_ate for an object: the estimate drawn as the result aligned it (W est X).
Status plot_object(const std::string& file, const ObjectTrajectoryResult& object,
                   const Trajectory& gt, const Trajectory& est, const std::string& title);

/// Translational (m) and rotational (deg) relative error over time, one panel each.
Status plot_rpe(const std::string& file, const RpeResult& rpe, const std::string& title);

/// The two world axes (0 = x, 1 = y, 2 = z) along which the positions extend most, in axis order.
std::pair<int, int> widest_axes(const Trajectory& trajectory);

}  // namespace df::eval
