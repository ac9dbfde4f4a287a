#include "sim/render.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sim/parallel.hpp"
#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr int kTile = 16;
constexpr double kNearZ = 0.02;

/// A shape placed relative to the camera for one frame.
struct Posed {
    const Shape* shape = nullptr;
    int material = 0;
    uint16_t instance = 0;
    Eigen::Matrix3d shape_R_camera;  ///< rays into the shape frame
    Vec3 origin_shape;               ///< camera centre in the shape frame
    Eigen::Matrix3d camera_R_shape;  ///< normals back into the camera frame
    double near_z = 0;               ///< smallest camera z of the shape's bounding box
};

/// Pixel rectangle [x0, x1) x [y0, y1) that may see the shape; false if none.
bool screen_rect(const Shape& shape, const Iso3& camera_T_shape, const RenderConfig& c,
                 double* near_z, int rect[4]) {
    const Vec3 h = local_half_extents(shape);
    Vec3 corners[8];
    double min_z = 1e300, max_z = -1e300;
    for (int k = 0; k < 8; ++k) {
        const Vec3 local((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                         (k & 4) ? h.z() : -h.z());
        corners[k] = camera_T_shape * local;
        min_z = std::min(min_z, corners[k].z());
        max_z = std::max(max_z, corners[k].z());
    }
    if (max_z < kNearZ) return false;
    *near_z = min_z;
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    auto extend = [&](const Vec3& p) {
        const double u = c.intrinsics.fx * p.x() / p.z() + c.intrinsics.cx;
        const double v = c.intrinsics.fy * p.y() / p.z() + c.intrinsics.cy;
        u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
    };
    // The box clipped by the plane z = kNearZ: corners in front, and where edges cross the plane.
    for (int k = 0; k < 8; ++k) {
        if (corners[k].z() >= kNearZ) extend(corners[k]);
        for (int bit : {1, 2, 4}) {
            if (k & bit) continue;
            const Vec3& a = corners[k];
            const Vec3& b = corners[k | bit];
            if ((a.z() < kNearZ) == (b.z() < kNearZ)) continue;
            const double f = (kNearZ - a.z()) / (b.z() - a.z());
            Vec3 p = a + f * (b - a);
            p.z() = kNearZ;
            extend(p);
        }
    }
    rect[0] = static_cast<int>(std::max(0.0, std::floor(std::max(u0, -1e6)) - 1));
    rect[1] = static_cast<int>(std::min<double>(c.width, std::ceil(std::min(u1, 1e6)) + 2));
    rect[2] = static_cast<int>(std::max(0.0, std::floor(std::max(v0, -1e6)) - 1));
    rect[3] = static_cast<int>(std::min<double>(c.height, std::ceil(std::min(v1, 1e6)) + 2));
    return rect[0] < rect[1] && rect[2] < rect[3];
}

struct Frame {
    std::vector<Posed> posed;
    std::vector<std::vector<int>> tiles;  ///< per tile: indices into posed, by near_z
    int tiles_x = 0;
};

void add_posed(const Shape& shape, const Iso3& world_T_shape, uint16_t instance,
               const Iso3& camera_T_world, const RenderConfig& c, Frame* frame) {
    const Iso3 camera_T_shape = camera_T_world * world_T_shape;
    Posed p;
    int rect[4];
    if (!screen_rect(shape, camera_T_shape, c, &p.near_z, rect)) return;
    p.shape = &shape;
    p.material = shape.material;
    p.instance = instance;
    p.camera_R_shape = camera_T_shape.linear();
    p.shape_R_camera = p.camera_R_shape.transpose();
    p.origin_shape = -(p.shape_R_camera * camera_T_shape.translation());
    const int index = static_cast<int>(frame->posed.size());
    frame->posed.push_back(p);
    for (int ty = rect[2] / kTile; ty <= (rect[3] - 1) / kTile; ++ty)
        for (int tx = rect[0] / kTile; tx <= (rect[1] - 1) / kTile; ++tx)
            frame->tiles[ty * frame->tiles_x + tx].push_back(index);
}

Frame prepare(const Scene& scene, const FrameState& state, const RenderConfig& c) {
    Frame frame;
    frame.tiles_x = (c.width + kTile - 1) / kTile;
    const int tiles_y = (c.height + kTile - 1) / kTile;
    frame.tiles.resize(static_cast<size_t>(frame.tiles_x) * tiles_y);
    const Iso3 camera_T_world = state.world_T_camera.inverse();
    for (const Shape& s : scene.statics)
        add_posed(s, s.parent_T_shape, 0, camera_T_world, c, &frame);
    for (size_t k = 0; k < scene.objects.size() && k < state.objects.size(); ++k) {
        const ObjectState& os = state.objects[k];
        for (const Shape& s : scene.objects[k].parts) {
            Iso3 world_T_parent = os.world_T_object;
            if (s.bone >= 0 && s.bone < static_cast<int>(os.object_T_bone.size()))
                world_T_parent = world_T_parent * os.object_T_bone[s.bone];
            add_posed(s, world_T_parent * s.parent_T_shape, static_cast<uint16_t>(k + 1),
                      camera_T_world, c, &frame);
        }
    }
    for (auto& list : frame.tiles) {
        std::stable_sort(list.begin(), list.end(), [&](int a, int b) {
            return frame.posed[a].near_z < frame.posed[b].near_z;
        });
    }
    return frame;
}

}  // namespace

RenderBuffers render(const Scene& scene, const FrameState& state, const RenderConfig& c) {
    RenderBuffers out;
    out.depth_m.create(c.height, c.width, CV_32FC1);
    out.instance.create(c.height, c.width, CV_16UC1);
    out.colour.create(c.height, c.width, CV_32FC3);
    out.incidence.create(c.height, c.width, CV_32FC1);
    out.dropout.create(c.height, c.width, CV_32FC1);
    const Frame frame = prepare(scene, state, c);

    const Eigen::Matrix3d world_R_camera = state.world_T_camera.linear();
    const Eigen::Matrix3d camera_R_world = world_R_camera.transpose();
    const Vec3 origin = state.world_T_camera.translation();
    const Iso3 camera_T_world = state.world_T_camera.inverse();
    std::vector<Vec3> lights_camera;
    std::vector<double> light_intensity, light_inv_falloff2;
    for (const Light& l : scene.lights) {
        lights_camera.push_back(camera_T_world * l.position);
        light_intensity.push_back(l.intensity);
        light_inv_falloff2.push_back(1.0 / (l.falloff_m * l.falloff_m));
    }
    std::vector<uint64_t> seeds(scene.materials.size());
    for (size_t m = 0; m < scene.materials.size(); ++m)
        seeds[m] = sim::texture_seed(scene, static_cast<int>(m));
    const Room& room = scene.room;

    parallel_rows(c.height, c.threads, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            auto* depth = out.depth_m.ptr<float>(y);
            auto* inst = out.instance.ptr<uint16_t>(y);
            auto* colour = out.colour.ptr<cv::Vec3f>(y);
            auto* incidence = out.incidence.ptr<float>(y);
            auto* dropout = out.dropout.ptr<float>(y);
            const std::vector<int>* row_tiles = &frame.tiles[(y / kTile) * frame.tiles_x];
            for (int x = 0; x < c.width; ++x) {
                const Vec3 d((x - c.intrinsics.cx) / c.intrinsics.fx,
                             (y - c.intrinsics.cy) / c.intrinsics.fy, 1.0);
                const Vec3 dw = world_R_camera * d;
                // The camera is inside the room: the ray leaves it through the nearest face.
                double best = 1e300;
                int face = -1;
                for (int i = 0; i < 3; ++i) {
                    if (dw[i] == 0) continue;
                    const double wall = dw[i] > 0 ? room.hi[i] : room.lo[i];
                    const double t = (wall - origin[i]) / dw[i];
                    if (t < best) {
                        best = t;
                        face = 2 * i + (dw[i] > 0 ? 1 : 0);
                    }
                }
                int hit = -1;
                const Vec3* hit_dir = nullptr;
                Vec3 ds_best;
                for (int index : row_tiles[x / kTile]) {
                    const Posed& p = frame.posed[index];
                    if (p.near_z >= best) break;
                    const Vec3 ds = p.shape_R_camera * d;
                    double t;
                    if (intersect(*p.shape, p.origin_shape, ds, 1e-9, best, &t)) {
                        best = t;
                        hit = index;
                        ds_best = ds;
                        hit_dir = &ds_best;
                    }
                }
                if (face < 0 || !(best > 0) || best > 1e6) {
                    depth[x] = 0;
                    inst[x] = 0;
                    colour[x] = cv::Vec3f(0, 0, 0);
                    incidence[x] = 0;
                    dropout[x] = 1;
                    continue;
                }
                Vec3 normal_camera;
                Rgb base;
                double material_dropout;
                Vec3 normal_world;
                double emission;
                if (hit < 0) {
                    const Vec3 pw = origin + best * dw;
                    const SurfacePoint sp = room_surface(room, face, pw);
                    const int m = room.materials[face];
                    base = albedo(scene.materials[m], pw, sp, seeds[m]);
                    normal_world = sp.normal;
                    normal_camera = camera_R_world * normal_world;
                    material_dropout = scene.materials[m].depth_dropout;
                    emission = scene.materials[m].emission;
                    inst[x] = 0;
                } else {
                    const Posed& p = frame.posed[hit];
                    const Vec3 ps = p.origin_shape + best * *hit_dir;
                    const SurfacePoint sp = surface_at(*p.shape, ps);
                    base = albedo(scene.materials[p.material], ps, sp, seeds[p.material]);
                    normal_camera = p.camera_R_shape * sp.normal;
                    normal_world = world_R_camera * normal_camera;
                    material_dropout = scene.materials[p.material].depth_dropout;
                    emission = scene.materials[p.material].emission;
                    inst[x] = p.instance;
                }
                const Vec3 pc = best * d;
                double shade = emission + scene.ambient * (0.85 + 0.15 * normal_world.z());
                for (size_t k = 0; k < lights_camera.size(); ++k) {
                    // intensity * cos(angle) / (1 + (dist / falloff)^2), one division a light.
                    const Vec3 to_light = lights_camera[k] - pc;
                    const double facing = normal_camera.dot(to_light);
                    if (facing <= 0) continue;
                    const double d2 = to_light.squaredNorm();
                    shade += light_intensity[k] * facing /
                             (std::sqrt(d2) * (1.0 + d2 * light_inv_falloff2[k]));
                }
                depth[x] = static_cast<float>(best);
                colour[x] = cv::Vec3f(static_cast<float>(base[0] * shade),
                                      static_cast<float>(base[1] * shade),
                                      static_cast<float>(base[2] * shade));
                incidence[x] = static_cast<float>(std::abs(normal_camera.dot(d)) / d.norm());
                dropout[x] = static_cast<float>(material_dropout);
            }
        }
    });
    return out;
}

}  // namespace df::sim
