#pragma once
/// A light copy of what SlamSystem has mapped, for people to look at (the live map view, the
/// Foxglove point cloud): the static map's stable surfels and every active object map's surfels
/// moved into the world frame by the object's pose, evenly thinned to a bounded count, and each
/// active object's extent in its own frame. DDS-free.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "slam_system/slam_system.hpp"

namespace df::slam {

struct SnapshotPoint {
    Eigen::Vector3f position_world = Eigen::Vector3f::Zero();  ///< metres
    uint8_t r = 0, g = 0, b = 0;
    uint32_t object_id = 0;  ///< 0: the static map; else the object map's id
};

struct ObjectExtent {
    int id = 0;
    int class_id = -1;
    Eigen::Vector3f min = Eigen::Vector3f::Zero();  ///< object frame, metres
    Eigen::Vector3f max = Eigen::Vector3f::Zero();
};

struct MapSnapshot {
    std::vector<SnapshotPoint> points;
    std::vector<ObjectExtent> objects;  ///< active object maps with at least one surfel
    size_t surfels = 0;                 ///< surfels the points were chosen from
};

/// The snapshot of `system`'s maps with at most max_points points: every k-th surfel of the
/// static map (stable ones) and of each active object map (all), k the same for all maps.
MapSnapshot map_snapshot(const SlamSystem& system, size_t max_points);

}  // namespace df::slam
