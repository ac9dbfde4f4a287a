#pragma once
/// What a generated sequence shows: a closed room, static furniture (world frame), dynamic
/// objects made of primitives (object or bone frame) with their motions, and lights.
/// Frames: world z up, floor at z = 0. Object frames: origin on the ground under the object,
/// x forward (direction of travel), z up.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sim/shapes.hpp"
#include "sim/texture.hpp"

namespace df::sim {

enum class ObjectKind {
    kRigid,     ///< a rigid object of a COCO class (car, chair, suitcase, ...)
    kNonRigid,  ///< an articulated body of a COCO class (person)
    kUnknown,   ///< a rigid object of no COCO class
};
const char* to_string(ObjectKind kind);

/// Pose of a dynamic object at one instant.
struct ObjectState {
    Iso3 world_T_object = Iso3::Identity();
    std::vector<Iso3> object_T_bone;  ///< articulated bodies only, indexed by Shape::bone
};

/// How an object moves: its state as a function of time (seconds from the first frame).
class Motion {
  public:
    virtual ~Motion() = default;
    virtual ObjectState at(double t_s) const = 0;
};

struct DynamicObject {
    std::string name;   ///< unique, e.g. "car_1"; names files under objects/ and models/
    int class_id = -1;  ///< COCO index in darknet coco.names order; -1 for unknown
    std::string class_name = "unknown";
    ObjectKind kind = ObjectKind::kUnknown;
    std::vector<Shape> parts;  ///< in the object frame (bone -1) or a bone frame
    std::shared_ptr<const Motion> motion;
};

/// The inside of an axis-aligned box, world frame. Faces: 0 x=lo (wall), 1 x=hi (wall),
/// 2 y=lo (wall), 3 y=hi (wall), 4 floor (z=lo), 5 ceiling (z=hi).
struct Room {
    Vec3 lo = Vec3(-3, -2, 0), hi = Vec3(3, 5, 2.7);
    std::array<int, 6> materials{};
};

struct Light {
    Vec3 position = Vec3(0, 1.5, 2.5);  ///< world, metres
    double intensity = 0.6;             ///< diffuse weight at distance 0
    double falloff_m = 3.0;             ///< distance at which the intensity halves
};

struct Scene {
    uint64_t seed = 1;
    std::vector<Material> materials;
    Room room;
    std::vector<Shape> statics;          ///< world frame; never move
    std::vector<DynamicObject> objects;  ///< instance id = index + 1
    std::vector<Light> lights;
    double ambient = 0.38;

    int add_material(Material material) {
        materials.push_back(std::move(material));
        return static_cast<int>(materials.size()) - 1;
    }
};

/// Seed of the procedural texture of material `material` (the same for renderer and models).
uint64_t texture_seed(const Scene& scene, int material);

/// Surface description of the room's inside at world point p on face `face`.
SurfacePoint room_surface(const Room& room, int face, const Vec3& p);

/// Places object-frame parts in the world: each part's pose becomes world_T_object * pose.
void place_static(Scene* scene, const std::vector<Shape>& parts, const Iso3& world_T_object);

/// world_T_object for an object standing at (x, y) with heading `yaw` (rad, about z).
Iso3 ground_pose(double x, double y, double yaw, double z = 0);

}  // namespace df::sim
