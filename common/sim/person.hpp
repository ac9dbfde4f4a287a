#pragma once
/// Persons: an articulated body of capsules and ellipsoids hung on 13 bones, walking along a
/// Route with swinging arms and legs, or sitting and gesturing. Non-rigid as a whole; the object
/// frame is the body's root (on the floor under the pelvis, x forward, z up).
#include <memory>
#include <string>

#include "sim/motion.hpp"
#include "sim/scene.hpp"

namespace df::sim {

enum PersonBone {
    kPelvis = 0,
    kTorso,
    kHead,
    kUpperArmL,
    kLowerArmL,
    kUpperArmR,
    kLowerArmR,
    kThighL,
    kShinL,
    kThighR,
    kShinR,
    kFootL,
    kFootR,
    kBoneCount
};

struct PersonStyle {
    Rgb shirt = Rgb(0.2, 0.35, 0.6), trousers = Rgb(0.15, 0.15, 0.2);
    Rgb skin = Rgb(0.85, 0.66, 0.52), hair = Rgb(0.18, 0.12, 0.08), shoes = Rgb(0.08, 0.08, 0.08);
    bool long_sleeves = false;
    Pattern shirt_pattern = Pattern::kNoise;  ///< kStripes or kChecker give a patterned shirt
    std::string shirt_photo;                  ///< photo printed on the chest ("" = none)
};

/// Builds a person's parts (adding its materials to the scene); `motion` must be a WalkingPerson
/// or SittingPerson (they fill object_T_bone).
DynamicObject make_person(Scene* scene, const PhotoLibrary* photos, const std::string& name,
                          const PersonStyle& style, std::shared_ptr<const Motion> motion);

/// Walks along a route: gait phase from the distance walked, swing amplitude from the speed
/// (limbs come to rest when the person stops).
class WalkingPerson : public Motion {
  public:
    explicit WalkingPerson(Route route, double stride_m = 1.35)
        : route_(std::move(route)), stride_m_(stride_m) {}
    ObjectState at(double t_s) const override;

  private:
    Route route_;
    double stride_m_;
};

/// Sits on a seat of height seat_m at a fixed place, leaning, turning the head and gesturing
/// (smooth seeded signals; `liveliness` 0..1 scales the gestures).
class SittingPerson : public Motion {
  public:
    SittingPerson(const Iso3& world_T_root, double seat_m, uint64_t seed, double liveliness = 0.6)
        : world_T_root_(world_T_root), seat_m_(seat_m), seed_(seed), liveliness_(liveliness) {}
    ObjectState at(double t_s) const override;

  private:
    Iso3 world_T_root_;
    double seat_m_;
    uint64_t seed_;
    double liveliness_;
};

/// Joint angles of a body (radians); positive flexion brings the limb forward.
struct BodyPose {
    double pelvis_z = 0.92, lean = 0, twist = 0, head_yaw = 0, head_pitch = 0;
    double hip[2] = {0, 0}, knee[2] = {0, 0}, shoulder[2] = {0, 0}, abduction[2] = {0.12, 0.12};
    double elbow[2] = {0.2, 0.2}, ankle[2] = {0, 0};
};

/// Forward kinematics: object_T_bone for every PersonBone.
std::vector<Iso3> person_bones(const BodyPose& pose);

}  // namespace df::sim
