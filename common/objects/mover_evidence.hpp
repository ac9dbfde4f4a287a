#pragma once
/// Whether an object map's object moves against the static map (config keep_until_moving): a
/// detected rigid object is a candidate mover, not a proven one. Its own tracking decides: the
/// object is proven moving once its surface moved from where it was first tracked (the anchor)
/// by more than the bound that depth noise and tracking error explain, on several tracked frames
/// in a row; a proven mover that stays within the bound long enough is still again and takes a
/// new anchor where it stopped. DDS-free: poses and numbers only.
#include <Eigen/Geometry>

#include "params/slam_params.hpp"

namespace df::objects {

/// The object as mover_displacement_m measures it: its centroid and its radius (RMS distance
/// of its surfels from the centroid), both in the object's own frame, metres.
struct ObjectExtent {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double radius_m = 0;
};

/// How far the surface of an object of `extent` moves from pose `a` to pose `b` (both
/// world_T_object): the centroid's displacement plus the rotation's angle times the radius
/// (metres; a bound on what a surface point at the radius moved).
double mover_displacement_m(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                            const ObjectExtent& extent);

/// The evidence kept per object map.
struct MoverEvidence {
    bool moving = false;    ///< proven mover: left out of the static map
    bool anchored = false;  ///< the anchor was set (by the first tracked frame)
    Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  ///< where it stood still
    int frames_over = 0;  ///< tracked frames in a row beyond the bound from the anchor
    /// While moving: where it was when the current run of frames within the bound began, and
    /// how many tracked frames that run has.
    Eigen::Isometry3d still_since = Eigen::Isometry3d::Identity();
    int frames_within = 0;
    int times_proven = 0;  ///< how often it became a proven mover
    /// While not moving: tracked frames within the bound since the last frame beyond it (or
    /// since the anchor); a candidate is settled (mover_settled) once this reaches
    /// settle_after_frames.
    int frames_settled = 0;
};

/// Whether the object is a settled candidate: not a proven mover, and tracked within the bound
/// for settle_after_frames tracked frames (config keep_until_moving: fused into the static map).
bool mover_settled(const MoverEvidence& evidence, const params::slam::Objects& config);

/// The bound (metres) at depth `depth_m` (the object's distance along the camera's z).
double mover_bound_m(double depth_m, const params::slam::Objects& config);

/// Updates `evidence` with one tracked pose of the object (`world_T_object`) seen at
/// `depth_m`. Returns true when its state (moving or still) changed.
bool update_mover(MoverEvidence* evidence, const Eigen::Isometry3d& world_T_object,
                  const ObjectExtent& extent, double depth_m, const params::slam::Objects& config);

}  // namespace df::objects
