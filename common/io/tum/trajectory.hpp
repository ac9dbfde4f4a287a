#pragma once
/// TUM trajectory files: one pose per line, "timestamp tx ty tz qx qy qz qw", '#' comments.
/// Each pose is world_T_camera (camera-to-world): t is the camera centre in world metres, q the
/// rotation from camera to world axes (Hamilton quaternion, stored x y z w in the file).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::io {

/// One line of a TUM trajectory: world_T_camera at stamp_s.
struct StampedPose {
    double stamp_s = 0;                                     ///< seconds
    Eigen::Vector3d t = Eigen::Vector3d::Zero();            ///< world_t_camera, metres
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< world_R_camera, unit norm
};

/// The pose of a frame stamped `sensor_ns` (nanoseconds) as a trajectory line.
inline StampedPose stamped_pose(int64_t sensor_ns, const Eigen::Isometry3d& world_T_x) {
    StampedPose p;
    p.stamp_s = static_cast<double>(sensor_ns) * 1e-9;
    p.t = world_T_x.translation();
    p.q = Eigen::Quaterniond(world_T_x.linear()).normalized();
    return p;
}

/// A trajectory line as world_T_x.
inline Eigen::Isometry3d isometry_of(const StampedPose& p) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = p.q.normalized().toRotationMatrix();
    pose.translation() = p.t;
    return pose;
}

struct TrajectoryParse {
    std::vector<StampedPose> poses;   ///< in file order; quaternions normalised
    std::vector<std::string> errors;  ///< "<file>:<line>: <what was expected, what was found>"
};

/// Reads a TUM trajectory. Malformed lines (fewer than 8 numbers, a non-numeric or non-finite
/// value, a stamp that io/tum/stamp.hpp's rules refuse, a zero quaternion) are skipped and
/// listed in `errors`; stamps are read exactly as nanoseconds, then stored as the nearest double
/// in seconds; fields after
/// the eighth are ignored, as TUM's tools do. Fails only if the file cannot be read.
Result<TrajectoryParse> read_tum_trajectory(const std::string& file);

/// Writes a TUM trajectory (stamps with 6 decimals, translation and quaternion with 9).
/// Creates or overwrites `file`; fails with kInvalidArgument for a non-finite value or a
/// negative stamp, with kIoError if the file cannot be written.
Status write_tum_trajectory(const std::string& file, const std::vector<StampedPose>& poses);

}  // namespace df::io
