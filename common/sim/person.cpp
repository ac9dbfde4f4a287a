#include "sim/person.hpp"

#include <algorithm>
#include <cmath>

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kThigh = 0.44, kShin = 0.42, kUpperArm = 0.29;

Iso3 translate(double x, double y, double z) {
    Iso3 t = Iso3::Identity();
    t.translation() = Vec3(x, y, z);
    return t;
}
Iso3 rot(const Vec3& axis, double angle) {
    Iso3 t = Iso3::Identity();
    t.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    return t;
}

Shape on_bone(Shape shape, int bone) {
    shape.bone = bone;
    return shape;
}

}  // namespace

std::vector<Iso3> person_bones(const BodyPose& b) {
    std::vector<Iso3> bones(kBoneCount, Iso3::Identity());
    const Vec3 X = Vec3::UnitX(), Y = Vec3::UnitY(), Z = Vec3::UnitZ();
    bones[kPelvis] = translate(0, 0, b.pelvis_z) * rot(Z, b.twist);
    bones[kTorso] =
        bones[kPelvis] * translate(0, 0, 0.08) * rot(Z, -1.6 * b.twist) * rot(Y, b.lean);
    bones[kHead] =
        bones[kTorso] * translate(0, 0, 0.54) * rot(Z, b.head_yaw) * rot(Y, b.head_pitch);
    for (int side = 0; side < 2; ++side) {
        const double s = side == 0 ? 1.0 : -1.0;  // 0 = left (+y), 1 = right (-y)
        const int upper = side == 0 ? kUpperArmL : kUpperArmR;
        const int lower = side == 0 ? kLowerArmL : kLowerArmR;
        const int thigh = side == 0 ? kThighL : kThighR;
        const int shin = side == 0 ? kShinL : kShinR;
        const int foot = side == 0 ? kFootL : kFootR;
        bones[upper] = bones[kTorso] * translate(0, s * 0.2, 0.42) * rot(X, s * b.abduction[side]) *
                       rot(Y, -b.shoulder[side]);
        bones[lower] = bones[upper] * translate(0, 0, -kUpperArm) * rot(Y, -b.elbow[side]);
        bones[thigh] = bones[kPelvis] * translate(0, s * 0.095, 0) * rot(Y, -b.hip[side]);
        bones[shin] = bones[thigh] * translate(0, 0, -kThigh) * rot(Y, b.knee[side]);
        bones[foot] = bones[shin] * translate(0, 0, -kShin) * rot(Y, b.ankle[side]);
    }
    return bones;
}

DynamicObject make_person(Scene* scene, const PhotoLibrary* photos, const std::string& name,
                          const PersonStyle& style, std::shared_ptr<const Motion> motion) {
    auto solid = [&](const std::string& what, const Rgb& colour, double grain = 0.05) {
        Material m;
        m.name = name + "_" + what;
        m.texture.pattern = Pattern::kNoise;
        m.texture.a = colour;
        m.texture.b = colour * 0.8;
        m.texture.scale = 0.08;
        m.texture.grain = grain;
        return scene->add_material(m);
    };
    Material shirt;
    shirt.name = name + "_shirt";
    shirt.texture.pattern = style.shirt_pattern;
    shirt.texture.a = style.shirt;
    shirt.texture.b = style.shirt_pattern == Pattern::kNoise ? Rgb(style.shirt * 0.75)
                                                             : Rgb(Rgb(0.92, 0.92, 0.9));
    shirt.texture.scale = style.shirt_pattern == Pattern::kNoise ? 0.1 : 0.05;
    shirt.texture.along_v = true;
    shirt.texture.grain = 0.08;
    const int sleeve = scene->add_material(shirt);
    if (!style.shirt_photo.empty()) {
        Decal print;
        print.photo = style.shirt_photo;
        print.image = photos ? photos->get(style.shirt_photo) : nullptr;
        print.centre = Vec3(0.12, 0, 0.04);
        print.right = Vec3::UnitY();
        print.up = Vec3::UnitZ();
        print.half_width = 0.1;
        print.half_height = 0.075;
        print.depth = 0.06;
        shirt.decals.push_back(print);
        shirt.name = name + "_shirt_front";
    }
    const int chest = style.shirt_photo.empty() ? sleeve : scene->add_material(shirt);
    const int trousers = solid("trousers", style.trousers, 0.08);
    const int skin = solid("skin", style.skin, 0.03);
    const int hair = solid("hair", style.hair, 0.15);
    const int shoes = solid("shoes", style.shoes, 0.05);
    const int eyes = solid("eyes", Rgb(0.05, 0.04, 0.04), 0.0);
    const int forearm = style.long_sleeves ? sleeve : skin;

    DynamicObject person;
    person.name = name;
    person.class_id = 0;
    person.class_name = "person";
    person.kind = ObjectKind::kNonRigid;
    person.motion = std::move(motion);
    auto& p = person.parts;
    p.push_back(
        on_bone(make_ellipsoid(Vec3(0, 0, 0.03), Vec3(0.115, 0.175, 0.12), trousers), kPelvis));
    p.push_back(on_bone(make_ellipsoid(Vec3(0, 0, 0.25), Vec3(0.12, 0.185, 0.28), chest), kTorso));
    p.push_back(
        on_bone(make_capsule(Vec3(0, -0.17, 0.4), Vec3(0, 0.17, 0.4), 0.065, sleeve), kTorso));
    p.push_back(on_bone(make_capsule(Vec3(0, 0, 0.44), Vec3(0, 0, 0.56), 0.05, skin), kTorso));
    p.push_back(on_bone(make_ellipsoid(Vec3(0.01, 0, 0.11), Vec3(0.1, 0.083, 0.118), skin), kHead));
    p.push_back(
        on_bone(make_ellipsoid(Vec3(-0.012, 0, 0.14), Vec3(0.102, 0.09, 0.1), hair), kHead));
    p.push_back(
        on_bone(make_ellipsoid(Vec3(0.11, 0, 0.095), Vec3(0.025, 0.015, 0.025), skin), kHead));
    for (double s : {1.0, -1.0}) {
        p.push_back(on_bone(
            make_ellipsoid(Vec3(0.096, s * 0.035, 0.125), Vec3::Constant(0.013), eyes), kHead));
    }
    for (int side = 0; side < 2; ++side) {
        const int upper = side == 0 ? kUpperArmL : kUpperArmR;
        const int lower = side == 0 ? kLowerArmL : kLowerArmR;
        const int thigh = side == 0 ? kThighL : kThighR;
        const int shin = side == 0 ? kShinL : kShinR;
        const int foot = side == 0 ? kFootL : kFootR;
        p.push_back(
            on_bone(make_capsule(Vec3(0, 0, -0.02), Vec3(0, 0, -0.27), 0.048, sleeve), upper));
        p.push_back(on_bone(make_capsule(Vec3(0, 0, 0), Vec3(0, 0, -0.23), 0.038, forearm), lower));
        p.push_back(
            on_bone(make_ellipsoid(Vec3(0, 0, -0.31), Vec3(0.045, 0.025, 0.07), skin), lower));
        p.push_back(
            on_bone(make_capsule(Vec3(0, 0, 0), Vec3(0, 0, -0.42), 0.075, trousers), thigh));
        p.push_back(on_bone(make_capsule(Vec3(0, 0, 0), Vec3(0, 0, -0.4), 0.055, trousers), shin));
        p.push_back(
            on_bone(make_ellipsoid(Vec3(0.05, 0, -0.02), Vec3(0.125, 0.05, 0.04), shoes), foot));
    }
    return person;
}

ObjectState WalkingPerson::at(double t_s) const {
    const Route::Sample s = route_.at(t_s);
    const double amp = std::clamp(s.speed / 1.0, 0.0, 1.0);
    const double phi = 2 * kPi * s.distance / stride_m_;
    BodyPose b;
    const double sin_phi = std::sin(phi);
    b.pelvis_z = 0.92 - amp * 0.06 * sin_phi * sin_phi;
    b.twist = amp * 0.07 * sin_phi;
    b.lean = amp * 0.06;
    b.head_yaw = 0.08 * std::sin(0.37 * t_s);
    for (int side = 0; side < 2; ++side) {
        const double ph = phi + side * kPi;
        const double c = std::max(0.0, std::cos(ph + kPi / 4));
        b.hip[side] = amp * 0.4 * std::sin(ph);
        b.knee[side] = amp * (0.08 + 0.62 * c * c);
        b.ankle[side] = b.hip[side] - b.knee[side];
        b.shoulder[side] = -amp * 0.35 * std::sin(ph);
        b.elbow[side] = 0.15 + amp * (0.2 + 0.3 * std::max(0.0, b.shoulder[side]));
    }
    ObjectState state;
    state.world_T_object = ground_pose(s.position.x(), s.position.y(), s.heading);
    state.object_T_bone = person_bones(b);
    return state;
}

ObjectState SittingPerson::at(double t_s) const {
    const double l = liveliness_;
    BodyPose b;
    b.pelvis_z = seat_m_ + 0.075;
    b.lean = 0.06 + 0.12 * l * wobble(seed_, 1, t_s, 0.03, 0.15);
    b.twist = 0.05 * l * wobble(seed_, 2, t_s, 0.03, 0.2);
    b.head_yaw = 0.5 * l * wobble(seed_, 3, t_s, 0.03, 0.2);
    b.head_pitch = 0.08 + 0.12 * l * wobble(seed_, 4, t_s, 0.05, 0.3);
    for (int side = 0; side < 2; ++side) {
        b.hip[side] = 1.5 + 0.05 * wobble(seed_, 10 + side, t_s, 0.02, 0.1);
        b.knee[side] = 1.4 + 0.15 * wobble(seed_, 12 + side, t_s, 0.02, 0.1);
        b.ankle[side] = b.hip[side] - b.knee[side];
        // Forearms rest forward; now and then one hand lifts into a gesture.
        const double gesture = std::max(0.0, wobble(seed_, 20 + side, t_s, 0.04, 0.12));
        b.shoulder[side] =
            0.45 + l * (0.25 * wobble(seed_, 14 + side, t_s, 0.1, 0.5) + 0.9 * gesture);
        b.elbow[side] = 1.2 + l * (0.35 * wobble(seed_, 16 + side, t_s, 0.1, 0.6) + 0.3 * gesture);
        b.abduction[side] = 0.18 + 0.1 * l * wobble(seed_, 18 + side, t_s, 0.1, 0.4);
    }
    ObjectState state;
    const double swivel = 0.15 * l * wobble(seed_, 9, t_s, 0.02, 0.12);
    state.world_T_object = world_T_root_ * rot(Vec3::UnitZ(), swivel);
    state.object_T_bone = person_bones(b);
    return state;
}

}  // namespace df::sim
