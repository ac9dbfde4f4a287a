#include "sim/models.hpp"

#include <algorithm>
#include <cmath>

#include "sim/rng.hpp"

namespace df::sim {
namespace {

/// How far a sample is pushed along its normal before testing whether it is buried.
constexpr double kProbe = 0.002;

struct Placed {
    const Shape* shape;
    Iso3 shape_T_frame;
    Eigen::AlignedBox3d box;  ///< in the frame the points are tested in
};

Placed place(const Shape& s, const Iso3& frame_T_shape) {
    Placed p{&s, frame_T_shape.inverse(), Eigen::AlignedBox3d()};
    const Vec3 h = local_half_extents(s);
    for (int k = 0; k < 8; ++k) {
        const Vec3 c((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
        p.box.extend(frame_T_shape * c);
    }
    return p;
}

bool buried(const std::vector<Placed>& solids, size_t self, const Vec3& q) {
    for (size_t k = 0; k < solids.size(); ++k) {
        if (k == self || !solids[k].box.contains(q)) continue;
        if (contains(*solids[k].shape, solids[k].shape_T_frame * q)) return true;
    }
    return false;
}

/// Appends the point at p_frame with normal n_frame, coloured with the material's albedo.
void add_coloured(const Scene& scene, int material, const Vec3& p_local, const SurfacePoint& sp,
                  const Vec3& p_frame, const Vec3& n_frame, io::PointCloud* out) {
    const Rgb c = albedo(scene.materials[material], p_local, sp, texture_seed(scene, material));
    out->positions.push_back(p_frame);
    out->normals.push_back(n_frame.cast<float>());
    out->colours.emplace_back(static_cast<uint8_t>(std::lround(255 * c[0])),
                              static_cast<uint8_t>(std::lround(255 * c[1])),
                              static_cast<uint8_t>(std::lround(255 * c[2])));
}

void sample_solids(const Scene& scene, const std::vector<Placed>& solids, const Room* room,
                   double spacing, uint64_t seed, io::PointCloud* out) {
    for (size_t k = 0; k < solids.size(); ++k) {
        const Shape& s = *solids[k].shape;
        const Iso3 frame_T_shape = solids[k].shape_T_frame.inverse();
        std::vector<SurfaceSample> samples;
        sample_surface(s, spacing, hash64(seed, k, 0x5A), &samples);
        for (const SurfaceSample& smp : samples) {
            const Vec3 p = frame_T_shape * smp.p;
            const Vec3 n = frame_T_shape.linear() * smp.n;
            const Vec3 probe = p + kProbe * n;
            if (room && ((probe.array() <= room->lo.array()).any() ||
                         (probe.array() >= room->hi.array()).any()))
                continue;
            if (buried(solids, k, probe)) continue;
            add_coloured(scene, s.material, smp.p, surface_at(s, smp.p), p, n, out);
        }
    }
}

}  // namespace

io::PointCloud sample_static_model(const Scene& scene, double spacing, uint64_t seed) {
    std::vector<Placed> solids;
    for (const Shape& s : scene.statics) solids.push_back(place(s, s.parent_T_shape));
    io::PointCloud out;
    const Room& room = scene.room;
    Rng rng(hash64(seed, 0x400D));
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
        const double eu = room.hi[ua] - room.lo[ua], ev = room.hi[va] - room.lo[va];
        const int nu = std::max(1, static_cast<int>(std::ceil(eu / spacing)));
        const int nv = std::max(1, static_cast<int>(std::ceil(ev / spacing)));
        for (int i = 0; i < nu; ++i) {
            for (int j = 0; j < nv; ++j) {
                Vec3 p;
                p[axis] = face % 2 == 0 ? room.lo[axis] : room.hi[axis];
                p[ua] = room.lo[ua] + eu * (i + rng.uniform(0.2, 0.8)) / nu;
                p[va] = room.lo[va] + ev * (j + rng.uniform(0.2, 0.8)) / nv;
                const SurfacePoint sp = room_surface(room, face, p);
                if (buried(solids, solids.size(), p + kProbe * sp.normal)) continue;
                add_coloured(scene, room.materials[face], p, sp, p, sp.normal, &out);
            }
        }
    }
    sample_solids(scene, solids, &room, spacing, seed, &out);
    return out;
}

io::PointCloud sample_object_model(const Scene& scene, size_t index, double spacing,
                                   uint64_t seed) {
    std::vector<Placed> solids;
    for (const Shape& s : scene.objects.at(index).parts)
        if (s.bone < 0) solids.push_back(place(s, s.parent_T_shape));
    io::PointCloud out;
    sample_solids(scene, solids, nullptr, spacing, hash64(seed, index, 0x0B), &out);
    return out;
}

}  // namespace df::sim
