#pragma once
/// Camera trajectories like those of the TUM RGB-D benchmark (fr3 static / xyz / rpy /
/// halfsphere) and a hand-held walk (Co-Fusion room4). All are smooth functions of time built
/// around a nominal pose (position looking at a target), with a seeded hand tremor.
#include <string>

#include "sim/shapes.hpp"

namespace df::sim {

enum class CameraMotion {
    kStatic,      ///< kept in place by hand: millimetre tremor only
    kXyz,         ///< translation along the camera's x, y and z axes, orientation kept
    kRpy,         ///< rotation about the camera's roll, pitch and yaw axes, position kept
    kHalfsphere,  ///< on a half sphere of 1 m diameter, always looking at the target
    kHandheld,    ///< walking to and fro beside the scene, looking at a wandering target
};
const char* to_string(CameraMotion motion);
/// Parses "static", "xyz", "rpy", "halfsphere", "handheld"; false for anything else.
bool parse_camera_motion(const std::string& text, CameraMotion* motion);

struct CameraPathConfig {
    CameraMotion motion = CameraMotion::kStatic;
    Vec3 position = Vec3(0, -0.5, 1.4);  ///< nominal camera centre, world metres
    Vec3 target = Vec3(0, 2.5, 0.8);     ///< nominal point looked at, world metres
    double amplitude = 1.0;              ///< scales the excursions of the motion
    double tremor = 1.0;                 ///< scales the hand tremor (0 = none)
    uint64_t seed = 1;
    /// A deliberate discontinuity (tests of tracking failure): from jump_at_s on, the camera is
    /// turned by jump_yaw_deg about the world z axis through its own centre, so that it
    /// suddenly sees another part of the room. Negative jump_at_s: no jump.
    double jump_at_s = -1.0;
    double jump_yaw_deg = 0.0;
};

/// world_T_camera (camera x right, y down, z forward) looking from `position` at `target`,
/// world z up.
Iso3 look_at(const Vec3& position, const Vec3& target);

/// world_T_camera at time t_s (seconds from the first frame).
Iso3 camera_pose(const CameraPathConfig& config, double t_s);

}  // namespace df::sim
