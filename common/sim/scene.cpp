#include "sim/scene.hpp"

#include "sim/rng.hpp"

namespace df::sim {

const char* to_string(ObjectKind kind) {
    switch (kind) {
        case ObjectKind::kRigid:
            return "rigid";
        case ObjectKind::kNonRigid:
            return "non_rigid";
        case ObjectKind::kUnknown:
            return "unknown";
    }
    return "unknown";
}

uint64_t texture_seed(const Scene& scene, int material) {
    return hash64(scene.seed, static_cast<uint64_t>(material), 0x7E);
}

SurfacePoint room_surface(const Room& room, int face, const Vec3& p) {
    SurfacePoint s;
    const int axis = face / 2;
    s.face = face;
    s.normal = Vec3::Zero();
    s.normal[axis] = (face % 2 == 0) ? 1.0 : -1.0;  // pointing into the room
    const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
    s.u = p[ua] - room.lo[ua];
    s.v = p[va] - room.lo[va];
    s.u_extent = room.hi[ua] - room.lo[ua];
    s.v_extent = room.hi[va] - room.lo[va];
    return s;
}

void place_static(Scene* scene, const std::vector<Shape>& parts, const Iso3& world_T_object) {
    for (Shape part : parts) {
        part.parent_T_shape = world_T_object * part.parent_T_shape;
        part.bone = -1;
        scene->statics.push_back(part);
    }
}

Iso3 ground_pose(double x, double y, double yaw, double z) {
    Iso3 pose = Iso3::Identity();
    pose.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    pose.translation() = Vec3(x, y, z);
    return pose;
}

}  // namespace df::sim
