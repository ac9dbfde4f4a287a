#include "sim/furniture.hpp"

#include <cmath>

#include "sim/objects.hpp"
#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Rgb jitter(const Rgb& c, Rng* rng, double amount) {
    return (c + Rgb(rng->uniform(-amount, amount), rng->uniform(-amount, amount),
                    rng->uniform(-amount, amount)))
        .cwiseMax(0.0)
        .cwiseMin(1.0);
}

void add_room(Scene* scene, Rng* rng) {
    Room& room = scene->room;
    room.lo = Vec3(-3.6, -2.0, 0.0);
    room.hi = Vec3(3.6, 5.0, 2.8);
    const Rgb wall = jitter(Rgb(0.86, 0.83, 0.76), rng, 0.04);
    const Rgb accent = jitter(Rgb(0.55, 0.68, 0.78), rng, 0.06);
    const int plaster =
        scene->add_material(make_material("wall", Pattern::kNoise, wall, wall * 0.9, 0.6, 0.05));
    const int plaster_accent = scene->add_material(
        make_material("wall_accent", Pattern::kNoise, accent, accent * 0.88, 0.6, 0.05));
    Material floor =
        make_material("floor_wood", Pattern::kPlanks, jitter(Rgb(0.62, 0.45, 0.3), rng, 0.05),
                      Rgb(0.4, 0.27, 0.16), 0.14, 0.05);
    floor.texture.grain_scale = 0.02;
    const int wood = scene->add_material(floor);
    const int ceiling = scene->add_material(make_material(
        "ceiling_tiles", Pattern::kTiles, Rgb(0.92, 0.92, 0.9), Rgb(0.6, 0.6, 0.6), 0.6, 0.04));
    room.materials = {plaster, plaster, plaster, plaster_accent, wood, ceiling};
}

std::vector<Shape> make_desk(Scene* scene, const Rgb& colour) {
    const int top = scene->add_material(
        make_material("desk_top", Pattern::kPlanks, colour, colour * 0.75, 0.2, 0.04));
    const int metal =
        scene->add_material(make_material("desk_legs", Pattern::kSolid, Rgb(0.25, 0.25, 0.27)));
    const int drawers = scene->add_material(make_material(
        "desk_drawers", Pattern::kStripes, colour * 0.9, Rgb(0.15, 0.12, 0.1), 0.2, 0.03));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.9, -0.4, 0.71), Vec3(0.9, 0.4, 0.745), top));
    for (double x : {0.86, -0.86})
        for (double y : {0.36, -0.36})
            p.push_back(
                make_box(Vec3(x - 0.025, y - 0.025, 0), Vec3(x + 0.025, y + 0.025, 0.71), metal));
    p.push_back(make_box(Vec3(-0.84, -0.38, 0.1), Vec3(-0.6, 0.3, 0.71), drawers));
    return p;
}

}  // namespace

std::vector<Shape> make_picture(Scene* scene, const PhotoLibrary* photos, const std::string& photo,
                                double height_m) {
    const auto image = photos ? photos->get(photo) : nullptr;
    const double aspect = image ? static_cast<double>(image->cols) / image->rows : 1.4;
    Material m = make_material("picture_" + photo, Pattern::kSolid, Rgb(0.25, 0.17, 0.1));
    Decal d;
    d.photo = photo;
    d.image = image;
    d.centre = Vec3(0.012, 0, 0);
    d.half_height = 0.5 * height_m;
    d.half_width = d.half_height * aspect;
    d.border = 0.035;
    d.border_colour = Rgb(0.22, 0.15, 0.09);
    d.depth = 0.005;
    m.decals.push_back(d);
    const int mat = scene->add_material(m);
    return {make_box(Vec3(-0.012, -d.half_width - d.border, -d.half_height - d.border),
                     Vec3(0.012, d.half_width + d.border, d.half_height + d.border), mat)};
}

std::vector<Shape> make_monitor(Scene* scene, const PhotoLibrary* photos,
                                const std::string& photo) {
    Material screen = make_material("monitor_screen", Pattern::kPanel, Rgb(0.05, 0.05, 0.06),
                                    Rgb(0.08, 0.08, 0.09), 0.015, 0.0);
    Decal d;
    d.photo = photo;
    d.image = photos ? photos->get(photo) : nullptr;
    d.centre = Vec3(0.02, 0, 0);
    d.half_width = 0.265;
    d.half_height = 0.165;
    d.depth = 0.005;
    screen.decals.push_back(d);
    screen.emission = 0.45;
    const int face = scene->add_material(screen);
    const int plastic =
        scene->add_material(make_material("monitor_plastic", Pattern::kSolid, Rgb(0.1, 0.1, 0.11)));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.02, -0.285, -0.185), Vec3(0.02, 0.285, 0.185), face));
    p.back().parent_T_shape.translation() = Vec3(0, 0, 0.3);
    p.push_back(make_box(Vec3(-0.12, -0.12, 0), Vec3(0.1, 0.12, 0.015), plastic));
    p.push_back(make_box(Vec3(-0.06, -0.03, 0.015), Vec3(-0.025, 0.03, 0.2), plastic));
    return p;
}

std::vector<Shape> make_bookshelf(Scene* scene, uint64_t seed) {
    Rng rng(seed);
    const int wood = scene->add_material(make_material(
        "shelf_wood", Pattern::kNoise, Rgb(0.45, 0.3, 0.18), Rgb(0.35, 0.22, 0.12), 0.08, 0.08));
    const Rgb palette[] = {{0.7, 0.1, 0.1},   {0.1, 0.3, 0.6},  {0.1, 0.45, 0.2},
                           {0.85, 0.75, 0.2}, {0.9, 0.9, 0.85}, {0.15, 0.15, 0.15},
                           {0.5, 0.2, 0.5},   {0.9, 0.45, 0.1}};
    std::vector<int> book_materials;
    for (const Rgb& c : palette) {
        Material m = make_material("book", Pattern::kStripes, jitter(c, &rng, 0.05),
                                   Rgb(0.92, 0.85, 0.6), 0.09, 0.05);
        m.texture.along_v = true;
        book_materials.push_back(scene->add_material(m));
    }
    std::vector<Shape> p;
    for (double y : {0.49, -0.49})
        p.push_back(make_box(Vec3(-0.16, y - 0.015, 0), Vec3(0.16, y + 0.015, 1.9), wood));
    p.push_back(make_box(Vec3(-0.16, -0.475, 0), Vec3(-0.145, 0.475, 1.9), wood));
    const double shelves[] = {0.0, 0.45, 0.85, 1.25, 1.65, 1.875};
    for (double z : shelves)
        p.push_back(make_box(Vec3(-0.145, -0.475, z), Vec3(0.16, 0.475, z + 0.025), wood));
    for (int s = 0; s + 1 < 6; ++s) {
        const double z0 = shelves[s] + 0.025, gap = shelves[s + 1] - z0;
        double y = -0.47;
        while (true) {
            const double w = rng.uniform(0.018, 0.055);
            if (y + w > 0.47) break;
            if (rng.uniform() < 0.08) {
                y += rng.uniform(0.03, 0.12);  // a gap
                continue;
            }
            const double h = std::min(gap - 0.02, rng.uniform(0.17, 0.32));
            const double depth = rng.uniform(0.16, 0.24);
            p.push_back(
                make_box(Vec3(0.14 - depth, y, z0), Vec3(0.14, y + w, z0 + h),
                         book_materials[rng.index(static_cast<int>(book_materials.size()))]));
            y += w + 0.002;
        }
    }
    return p;
}

std::vector<Shape> make_sofa(Scene* scene, const Rgb& colour) {
    const int fabric = scene->add_material(
        make_material("sofa_fabric", Pattern::kNoise, colour, colour * 0.8, 0.05, 0.12));
    const int feet =
        scene->add_material(make_material("sofa_feet", Pattern::kSolid, Rgb(0.15, 0.1, 0.06)));
    std::vector<Shape> p;
    p.push_back(make_box(Vec3(-0.45, -0.95, 0.1), Vec3(0.45, 0.95, 0.4), fabric));
    for (double y : {0.4, -0.4})
        p.push_back(make_box(Vec3(-0.28, y - 0.4, 0.4), Vec3(0.44, y + 0.4, 0.5), fabric));
    p.push_back(make_box(Vec3(-0.45, -0.95, 0.4), Vec3(-0.25, 0.95, 0.88), fabric));
    for (double y : {0.87, -0.87})
        p.push_back(make_box(Vec3(-0.45, y - 0.08, 0.4), Vec3(0.45, y + 0.08, 0.64), fabric));
    for (double x : {0.4, -0.4})
        for (double y : {0.9, -0.9})
            p.push_back(make_box(Vec3(x - 0.03, y - 0.03, 0), Vec3(x + 0.03, y + 0.03, 0.1), feet));
    return p;
}

Office build_office(Scene* scene, const PhotoLibrary* photos, uint64_t seed) {
    Rng rng(seed ^ 0x0FF1CEull);
    add_room(scene, &rng);
    Office office;
    const double pi = kPi;

    place_static(scene, make_desk(scene, jitter(Rgb(0.72, 0.58, 0.42), &rng, 0.05)),
                 ground_pose(0, 2.4, 0));
    place_static(scene, make_monitor(scene, photos, "dog"),
                 ground_pose(0.62, 2.3, -pi / 2 + 0.35, 0.745));
    {
        const int keys = scene->add_material(make_material(
            "keyboard", Pattern::kTiles, Rgb(0.2, 0.2, 0.22), Rgb(0.05, 0.05, 0.05), 0.019, 0.02));
        scene->statics.push_back(make_box(Vec3(-0.62, 2.48, 0.745), Vec3(-0.18, 2.63, 0.77), keys));
        const int mug = scene->add_material(make_material(
            "mug", Pattern::kStripes, Rgb(0.9, 0.9, 0.88), Rgb(0.75, 0.1, 0.1), 0.04, 0.02));
        const double mx = rng.uniform(-0.1, 0.15);
        scene->statics.push_back(
            make_frustum(Vec3(mx, 2.2, 0.745), 0.038, Vec3(mx, 2.2, 0.85), 0.042, mug));
        const Rgb covers[] = {{0.2, 0.3, 0.6}, {0.7, 0.2, 0.15}, {0.9, 0.8, 0.3}};
        double z = 0.745;
        for (int k = 0; k < 3; ++k) {
            const int m = scene->add_material(make_material("desk_book", Pattern::kPanel, covers[k],
                                                            Rgb(0.95, 0.95, 0.9), 0.012, 0.04));
            const double h = rng.uniform(0.025, 0.045);
            Iso3 pose = ground_pose(-0.72, 2.18, rng.uniform(-0.3, 0.3), z + 0.5 * h);
            scene->statics.push_back(make_box(Vec3(0.12, 0.09, 0.5 * h), pose, m));
            z += h;
        }
    }
    // Two office chairs behind the desk, facing the camera side (-y).
    office.seat_height_m = 0.45;
    for (int k = 0; k < 2; ++k) {
        const double x = k == 0 ? -0.3 : 0.42;
        const double yaw = -pi / 2 + (k == 0 ? 0.12 : -0.1);
        const Iso3 pose = ground_pose(x, 3.05, yaw);
        place_static(scene, make_office_chair(scene, jitter(Rgb(0.15, 0.2, 0.35), &rng, 0.05)),
                     pose);
        office.seats[k] = pose;
    }
    place_static(scene, make_bookshelf(scene, seed ^ 0xB00C), ground_pose(-1.6, 4.82, -pi / 2));
    place_static(scene, make_bookshelf(scene, seed ^ 0xB00D), ground_pose(-2.65, 4.82, -pi / 2));
    place_static(scene, make_sofa(scene, jitter(Rgb(0.2, 0.45, 0.45), &rng, 0.06)),
                 ground_pose(3.1, 3.4, pi));
    place_static(scene, make_teddy_bear(scene, Rgb(0.55, 0.35, 0.18)),
                 ground_pose(3.12, 3.85, pi + 0.2, 0.5));
    place_static(scene, make_potted_plant(scene, 1.3, seed ^ 0x91), ground_pose(-3.2, 4.55, 0));
    place_static(scene, make_potted_plant(scene, 1.0, seed ^ 0x92), ground_pose(3.15, 2.0, 0));
    place_static(scene, make_chair(scene, jitter(Rgb(0.6, 0.4, 0.22), &rng, 0.05)),
                 ground_pose(-2.9, -1.3, 0.4));

    // Framed photos on the walls.
    place_static(scene, make_picture(scene, photos, "scream", 0.6),
                 ground_pose(-3.588, 2.3, 0, 1.55));
    place_static(scene, make_picture(scene, photos, "eagle", 0.5),
                 ground_pose(-3.588, 0.6, 0, 1.5));
    place_static(scene, make_picture(scene, photos, "horses", 0.55),
                 ground_pose(0.3, 4.988, -pi / 2, 1.6));
    place_static(scene, make_picture(scene, photos, "giraffe", 0.5),
                 ground_pose(3.588, 1.6, pi, 1.55));
    place_static(scene, make_picture(scene, photos, "kite", 0.5),
                 ground_pose(3.588, 3.4, pi, 1.45));

    {
        const int board = scene->add_material(make_material(
            "whiteboard", Pattern::kPanel, Rgb(0.95, 0.95, 0.95), Rgb(0.6, 0.6, 0.62), 0.03, 0.02));
        scene->statics.push_back(make_box(Vec3(1.2, 4.975, 0.9), Vec3(2.6, 5.0, 1.9), board));
        const int cabinet = scene->add_material(make_material(
            "cabinet", Pattern::kPanel, Rgb(0.75, 0.72, 0.65), Rgb(0.4, 0.38, 0.35), 0.03, 0.04));
        scene->statics.push_back(make_box(Vec3(1.3, 4.55, 0), Vec3(2.5, 5.0, 0.8), cabinet));
        const int door = scene->add_material(make_material(
            "door", Pattern::kPanel, Rgb(0.6, 0.42, 0.26), Rgb(0.5, 0.34, 0.2), 0.09, 0.06));
        scene->statics.push_back(make_box(Vec3(-3.6, -1.2, 0), Vec3(-3.56, -0.3, 2.05), door));
        const int metal =
            scene->add_material(make_material("handle", Pattern::kSolid, Rgb(0.7, 0.7, 0.72)));
        scene->statics.push_back(
            make_ellipsoid(Vec3(-3.54, -0.4, 1.0), Vec3(0.03, 0.06, 0.025), metal));
        Material sky = make_material("window", Pattern::kNoise, Rgb(0.85, 0.92, 1.0),
                                     Rgb(0.7, 0.8, 0.95), 0.4, 0.02);
        sky.emission = 0.8;
        sky.depth_dropout = 0.7;
        const int window = scene->add_material(sky);
        const int frame = scene->add_material(
            make_material("window_frame", Pattern::kSolid, Rgb(0.93, 0.93, 0.93)));
        scene->statics.push_back(make_box(Vec3(3.575, -0.9, 0.95), Vec3(3.6, 0.6, 2.2), frame));
        scene->statics.push_back(make_box(Vec3(3.56, -0.85, 1.0), Vec3(3.58, 0.55, 2.15), window));
        const int radiator =
            scene->add_material(make_material("radiator", Pattern::kStripes, Rgb(0.95, 0.95, 0.95),
                                              Rgb(0.75, 0.75, 0.75), 0.05, 0.01));
        scene->statics.push_back(make_box(Vec3(3.5, -0.8, 0.15), Vec3(3.58, 0.5, 0.7), radiator));
        const int rug = scene->add_material(make_material(
            "rug", Pattern::kChecker, Rgb(0.65, 0.2, 0.18), Rgb(0.85, 0.75, 0.55), 0.3, 0.12));
        scene->statics.push_back(make_box(Vec3(-1.3, 0.3, 0), Vec3(1.3, 1.9, 0.008), rug));
        Material lamp = make_material("ceiling_lamp", Pattern::kSolid, Rgb(1.0, 1.0, 0.97));
        lamp.emission = 1.6;
        const int lamp_m = scene->add_material(lamp);
        for (const Vec3& c :
             {Vec3(-1.2, 1.2, 2.8), Vec3(1.2, 1.2, 2.8), Vec3(-1.2, 3.6, 2.8), Vec3(1.2, 3.6, 2.8)})
            scene->statics.push_back(
                make_box(c - Vec3(0.3, 0.3, 0.03), c + Vec3(0.3, 0.3, 0.0), lamp_m));
    }
    scene->lights = {{Vec3(-1.2, 1.2, 2.6), 0.35, 3.0},
                     {Vec3(1.2, 1.2, 2.6), 0.35, 3.0},
                     {Vec3(-1.2, 3.6, 2.6), 0.3, 3.0},
                     {Vec3(1.2, 3.6, 2.6), 0.3, 3.0}};
    scene->ambient = 0.4;
    return office;
}

}  // namespace df::sim
