#include "sim/objects.hpp"

#include <cmath>

#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Iso3 pose_ry(const Vec3& centre, double angle) {
    Iso3 p = Iso3::Identity();
    p.linear() = Eigen::AngleAxisd(angle, Vec3::UnitY()).toRotationMatrix();
    p.translation() = centre;
    return p;
}

}  // namespace

std::vector<Shape> make_car(Scene* scene, const Rgb& paint, double s) {
    const int body = scene->add_material(
        make_material("car_paint", Pattern::kNoise, paint, paint * 0.85, 0.3, 0.03));
    Material glass =
        make_material("car_glass", Pattern::kPanel, Rgb(0.08, 0.1, 0.13), paint, 0.07 * s, 0.05);
    const int windows = scene->add_material(glass);
    const int dark =
        scene->add_material(make_material("car_trim", Pattern::kSolid, Rgb(0.09, 0.09, 0.1)));
    Material tyre_m = make_material("car_tyre", Pattern::kNoise, Rgb(0.07, 0.07, 0.07),
                                    Rgb(0.12, 0.12, 0.12), 0.05, 0.1);
    tyre_m.depth_dropout = 0.05;
    const int tyre = scene->add_material(tyre_m);
    const int hub = scene->add_material(make_material(
        "car_hub", Pattern::kRings, Rgb(0.75, 0.75, 0.78), Rgb(0.3, 0.3, 0.32), 0.05 * s, 0.02));
    Material lamp = make_material("car_headlight", Pattern::kSolid, Rgb(0.95, 0.95, 0.85));
    lamp.emission = 0.3;
    const int head = scene->add_material(lamp);
    const int tail =
        scene->add_material(make_material("car_taillight", Pattern::kSolid, Rgb(0.8, 0.08, 0.06)));
    const int plate = scene->add_material(make_material(
        "car_plate", Pattern::kPanel, Rgb(0.95, 0.95, 0.92), Rgb(0.1, 0.1, 0.1), 0.015 * s, 0.0));
    auto box = [&](const Vec3& lo, const Vec3& hi, int m) { return make_box(lo * s, hi * s, m); };
    std::vector<Shape> p;
    p.push_back(box({-2.1, -0.86, 0.28}, {2.1, 0.86, 0.86}, body));
    p.push_back(box({-1.3, -0.76, 0.85}, {0.65, 0.76, 1.4}, windows));
    p.push_back(box({-1.28, -0.74, 1.39}, {0.62, 0.74, 1.45}, body));
    // Windshield and rear window: thick boxes tilted so one face makes the slope.
    {
        const double a = std::atan2(0.54, 0.7);
        const Vec3 n(std::sin(a), 0, std::cos(a));
        const Vec3 top(1.0, 0, 1.13);
        p.push_back(
            make_box(Vec3(0.443, 0.75, 0.25) * s, pose_ry((top - 0.25 * n) * s, a), windows));
    }
    {
        const double a = -std::atan2(0.5, 0.45);
        const Vec3 n(std::sin(a), 0, std::cos(a));
        const Vec3 top(-1.525, 0, 1.15);
        p.push_back(make_box(Vec3(0.336, 0.75, 0.2) * s, pose_ry((top - 0.2 * n) * s, a), windows));
    }
    for (double x : {1.27, -1.27}) {
        for (double side : {1.0, -1.0}) {
            p.push_back(make_frustum(Vec3(x, side * 0.7, 0.31) * s, 0.31 * s,
                                     Vec3(x, side * 0.9, 0.31) * s, 0.31 * s, tyre));
            p.push_back(make_frustum(Vec3(x, side * 0.89, 0.31) * s, 0.19 * s,
                                     Vec3(x, side * 0.915, 0.31) * s, 0.19 * s, hub));
        }
    }
    for (double sign : {1.0, -1.0}) {
        p.push_back(
            box({sign > 0 ? 2.05 : -2.16, -0.84, 0.3}, {sign > 0 ? 2.16 : -2.05, 0.84, 0.5}, dark));
        p.push_back(
            box({sign > 0 ? 2.1 : -2.17, -0.2, 0.33}, {sign > 0 ? 2.17 : -2.1, 0.2, 0.45}, plate));
        p.push_back(
            box({0.55, sign > 0 ? 0.86 : -0.98, 0.95}, {0.7, sign > 0 ? 0.98 : -0.86, 1.05}, body));
    }
    for (double y : {0.6, -0.6}) {
        p.push_back(make_ellipsoid(Vec3(2.08, y, 0.72) * s, Vec3(0.05, 0.17, 0.07) * s, head));
        p.push_back(box({-2.13, y - 0.15, 0.68}, {-2.08, y + 0.15, 0.8}, tail));
    }
    p.push_back(box({2.08, -0.35, 0.55}, {2.13, 0.35, 0.7}, dark));
    return p;
}

std::vector<Shape> make_chair(Scene* scene, const Rgb& colour) {
    const int wood = scene->add_material(
        make_material("chair_wood", Pattern::kNoise, colour, colour * 0.7, 0.06, 0.08));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.22, -0.22, 0.43), Vec3(0.22, 0.22, 0.47), wood));
    for (double x : {0.19, -0.19})
        for (double y : {0.19, -0.19})
            p.push_back(
                make_box(Vec3(x - 0.018, y - 0.018, 0), Vec3(x + 0.018, y + 0.018, 0.43), wood));
    for (double y : {0.19, -0.19})
        p.push_back(make_box(Vec3(-0.208, y - 0.018, 0.47), Vec3(-0.172, y + 0.018, 0.93), wood));
    p.push_back(make_box(Vec3(-0.21, -0.2, 0.66), Vec3(-0.18, 0.2, 0.91), wood));
    p.push_back(make_box(Vec3(-0.205, -0.19, 0.55), Vec3(-0.185, 0.19, 0.59), wood));
    return p;
}

std::vector<Shape> make_office_chair(Scene* scene, const Rgb& colour) {
    const int fabric = scene->add_material(
        make_material("office_chair_fabric", Pattern::kNoise, colour, colour * 0.75, 0.04, 0.12));
    const int metal = scene->add_material(
        make_material("office_chair_metal", Pattern::kSolid, Rgb(0.12, 0.12, 0.13)));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.24, -0.24, 0.37), Vec3(0.24, 0.24, 0.45), fabric));
    {
        Iso3 back = Iso3::Identity();
        back.linear() = Eigen::AngleAxisd(-0.12, Vec3::UnitY()).toRotationMatrix();
        back.translation() = Vec3(-0.27, 0, 0.8);
        p.push_back(make_box(Vec3(0.035, 0.22, 0.26), back, fabric));
    }
    p.push_back(make_box(Vec3(-0.26, -0.03, 0.42), Vec3(-0.22, 0.03, 0.58), metal));
    p.push_back(make_frustum(Vec3(0, 0, 0.08), 0.028, Vec3(0, 0, 0.38), 0.028, metal));
    for (int k = 0; k < 5; ++k) {
        const double a = 2 * kPi * k / 5 + 0.3;
        const Vec3 dir(std::cos(a), std::sin(a), 0);
        p.push_back(make_capsule(Vec3(0, 0, 0.07), dir * 0.3 + Vec3(0, 0, 0.07), 0.022, metal));
        p.push_back(make_ellipsoid(dir * 0.3 + Vec3(0, 0, 0.03), Vec3::Constant(0.03), metal));
    }
    for (double y : {0.26, -0.26}) {
        p.push_back(make_box(Vec3(-0.2, y - 0.025, 0.6), Vec3(0.14, y + 0.025, 0.63), metal));
        p.push_back(make_box(Vec3(-0.05, y - 0.012, 0.45), Vec3(-0.02, y + 0.012, 0.6), metal));
    }
    return p;
}

std::vector<Shape> make_suitcase(Scene* scene, const Rgb& colour, const PhotoLibrary* photos) {
    Material shell =
        make_material("suitcase_shell", Pattern::kStripes, colour, colour * 0.82, 0.05, 0.04);
    Decal sticker;
    sticker.photo = "kite";
    sticker.image = photos ? photos->get("kite") : nullptr;
    sticker.centre = Vec3(0.125, 0.05, 0.1);
    sticker.right = Vec3::UnitY();
    sticker.up = Vec3::UnitZ();
    sticker.half_width = 0.08;
    sticker.half_height = 0.055;
    sticker.border = 0.006;
    sticker.border_colour = Rgb(0.95, 0.95, 0.95);
    sticker.depth = 0.01;
    shell.decals.push_back(sticker);
    const int body = scene->add_material(shell);
    const int trim =
        scene->add_material(make_material("suitcase_trim", Pattern::kSolid, Rgb(0.1, 0.1, 0.1)));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.125, -0.21, 0.06), Vec3(0.125, 0.21, 0.68), body));
    p.push_back(make_box(Vec3(-0.13, -0.215, 0.36), Vec3(0.13, 0.215, 0.38), trim));
    for (double y : {0.08, -0.08})
        p.push_back(make_box(Vec3(-0.115, y - 0.012, 0.68), Vec3(-0.09, y + 0.012, 0.95), trim));
    p.push_back(make_capsule(Vec3(-0.1025, -0.1, 0.96), Vec3(-0.1025, 0.1, 0.96), 0.018, trim));
    p.push_back(make_capsule(Vec3(0, -0.07, 0.7), Vec3(0, 0.07, 0.7), 0.015, trim));
    for (double x : {0.09, -0.09})
        for (double y : {0.17, -0.17})
            p.push_back(make_ellipsoid(Vec3(x, y, 0.03), Vec3(0.03, 0.015, 0.03), trim));
    return p;
}

std::vector<Shape> make_teddy_bear(Scene* scene, const Rgb& fur) {
    const int body =
        scene->add_material(make_material("teddy_fur", Pattern::kNoise, fur, fur * 0.7, 0.02, 0.2));
    const int light = scene->add_material(make_material(
        "teddy_muzzle", Pattern::kNoise, Rgb(0.85, 0.72, 0.55), Rgb(0.75, 0.6, 0.45), 0.02, 0.1));
    const int dark =
        scene->add_material(make_material("teddy_eyes", Pattern::kSolid, Rgb(0.04, 0.03, 0.03)));
    std::vector<Shape> p;
    p.push_back(make_ellipsoid(Vec3(0, 0, 0.17), Vec3(0.12, 0.13, 0.16), body));
    p.push_back(make_ellipsoid(Vec3(0.02, 0, 0.38), Vec3(0.1, 0.105, 0.095), body));
    for (double y : {0.075, -0.075}) {
        p.push_back(make_ellipsoid(Vec3(0, y, 0.465), Vec3(0.025, 0.04, 0.04), body));
        p.push_back(make_ellipsoid(Vec3(0.1, y * 0.5, 0.41), Vec3::Constant(0.014), dark));
        p.push_back(make_capsule(Vec3(0.02, y * 1.8, 0.27), Vec3(0.1, y * 2.2, 0.14), 0.04, body));
        p.push_back(make_capsule(Vec3(0.03, y * 1.1, 0.06), Vec3(0.2, y * 1.3, 0.05), 0.05, body));
        p.push_back(make_ellipsoid(Vec3(0.24, y * 1.3, 0.055), Vec3(0.02, 0.045, 0.045), light));
    }
    p.push_back(make_ellipsoid(Vec3(0.105, 0, 0.355), Vec3(0.045, 0.05, 0.04), light));
    p.push_back(make_ellipsoid(Vec3(0.148, 0, 0.37), Vec3(0.012, 0.018, 0.012), dark));
    p.push_back(make_ellipsoid(Vec3(0.09, 0, 0.17), Vec3(0.05, 0.08, 0.09), light));
    return p;
}

std::vector<Shape> make_potted_plant(Scene* scene, double height, uint64_t seed) {
    const int pot = scene->add_material(make_material(
        "plant_pot", Pattern::kNoise, Rgb(0.62, 0.3, 0.18), Rgb(0.5, 0.24, 0.14), 0.05, 0.06));
    const int soil = scene->add_material(make_material(
        "plant_soil", Pattern::kNoise, Rgb(0.2, 0.13, 0.08), Rgb(0.12, 0.08, 0.05), 0.01, 0.2));
    const int leaves =
        scene->add_material(make_material("plant_leaves", Pattern::kNoise, Rgb(0.18, 0.45, 0.15),
                                          Rgb(0.08, 0.25, 0.06), 0.025, 0.25));
    const double pot_h = 0.28 * height / 1.0;
    std::vector<Shape> p;
    p.push_back(make_frustum(Vec3(0, 0, 0), 0.12, Vec3(0, 0, pot_h), 0.16, pot));
    p.push_back(make_frustum(Vec3(0, 0, pot_h), 0.15, Vec3(0, 0, pot_h + 0.005), 0.15, soil));
    Rng rng(seed);
    for (int k = 0; k < 9; ++k) {
        const double z = pot_h + (height - pot_h) * (0.25 + 0.6 * k / 8.0);
        const double a = rng.uniform(0, 2 * kPi), r = 0.06 + 0.12 * rng.uniform();
        const Vec3 c(r * std::cos(a), r * std::sin(a), z);
        const double size = 0.16 * (1.2 - 0.5 * k / 8.0);
        p.push_back(make_ellipsoid(c, Vec3(size, size * 0.8, size * 0.7), leaves,
                                   Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix()));
    }
    return p;
}

std::vector<Shape> make_roller(Scene* scene, const Rgb& a, const Rgb& b) {
    const int shell =
        scene->add_material(make_material("roller_shell", Pattern::kChecker, a, b, 0.105, 0.05));
    const int cap =
        scene->add_material(make_material("roller_cap", Pattern::kRings, b, a, 0.03, 0.03));
    std::vector<Shape> p;
    p.push_back(make_capsule(Vec3(0, -0.2, 0), Vec3(0, 0.2, 0), 0.2, shell));
    for (double y : {1.0, -1.0})
        p.push_back(make_frustum(Vec3(0, y * 0.3, 0), 0.12, Vec3(0, y * 0.43, 0), 0.09, cap));
    return p;
}

std::vector<Shape> make_totem(Scene* scene, const Rgb& a, const Rgb& b) {
    const int m1 = scene->add_material(make_material("totem_base", Pattern::kStripes, a, b, 0.06));
    const int m2 = scene->add_material(make_material("totem_ball", Pattern::kChecker, b, a, 0.07));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.17, -0.12, 0), Vec3(0.17, 0.12, 0.22), m1));
    p.push_back(make_ellipsoid(Vec3(0.03, 0, 0.33), Vec3(0.16, 0.13, 0.11), m2));
    p.push_back(make_frustum(Vec3(-0.02, 0, 0.42), 0.1, Vec3(-0.06, 0.02, 0.62), 0.02, m1));
    return p;
}

}  // namespace df::sim
