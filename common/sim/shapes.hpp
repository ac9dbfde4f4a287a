#pragma once
/// Solid primitives with analytic ray intersection, surface frames and surface sampling.
/// Every primitive lives in its own local frame (metres); a Shape places it in its parent frame
/// (the world for static furniture, an object or a bone for dynamic things).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace df::sim {

using Vec3 = Eigen::Vector3d;
using Iso3 = Eigen::Isometry3d;

enum class ShapeType : unsigned char {
    kBox,        ///< size = half extents (x, y, z)
    kEllipsoid,  ///< size = radii (x, y, z); a sphere has equal radii
    kFrustum,    ///< capped truncated cone along local z: size = (radius at -h, radius at +h, h)
    kCapsule,    ///< segment z in [-h, h] swept by a ball: size = (radius, unused, h)
};

struct Shape {
    ShapeType type = ShapeType::kBox;
    Vec3 size = Vec3::Constant(0.5);
    Iso3 parent_T_shape = Iso3::Identity();
    int material = 0;  ///< index into Scene::materials
    int bone = -1;     ///< articulated bodies: index of the bone the shape hangs on; -1 = root
};

/// Axis-aligned box [lo, hi] in the parent frame.
Shape make_box(const Vec3& lo, const Vec3& hi, int material);
/// Box of half extents `half` at `parent_T_shape`.
Shape make_box(const Vec3& half, const Iso3& parent_T_shape, int material);
Shape make_ellipsoid(const Vec3& centre, const Vec3& radii, int material,
                     const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());
/// Capped cylinder or cone frustum from p0 (radius r0) to p1 (radius r1).
Shape make_frustum(const Vec3& p0, double r0, const Vec3& p1, double r1, int material);
Shape make_capsule(const Vec3& p0, const Vec3& p1, double radius, int material);

/// Rotation whose z axis is `axis` (normalised inside); x and y are chosen deterministically.
Eigen::Matrix3d frame_with_z(const Vec3& axis);

/// Nearest intersection parameter t in (t_min, t_max) of the ray o + t d (local frame, d need
/// not be unit). Returns false if none. Rays starting inside a solid see its inside surface.
bool intersect(const Shape& shape, const Vec3& o, const Vec3& d, double t_min, double t_max,
               double* t);

/// Local description of a surface point: what textures and shading need.
struct SurfacePoint {
    Vec3 normal = Vec3::UnitZ();  ///< outward unit normal, local frame
    int face = 0;         ///< box: 0..5 = +x,-x,+y,-y,+z,-z; frustum: 0 side, 1 top, 2 bottom
    double u = 0, v = 0;  ///< in-surface coordinates, metres
    double u_extent = 1, v_extent = 1;  ///< size of the face in u and v, metres
};

/// Surface description at a local point p on (or within rounding of) the shape's surface.
SurfacePoint surface_at(const Shape& shape, const Vec3& p);

/// True if the local point lies strictly inside the solid.
bool contains(const Shape& shape, const Vec3& p);

/// Half extents of the shape's local axis-aligned bounding box (centred at the local origin).
Vec3 local_half_extents(const Shape& shape);

/// A sample of a surface, local frame.
struct SurfaceSample {
    Vec3 p, n;
};

/// Samples the shape's surface with about one point per spacing^2 (jittered strata, so coverage
/// has no holes larger than about `spacing`). Appends to `out`; deterministic given `seed`.
void sample_surface(const Shape& shape, double spacing, uint64_t seed,
                    std::vector<SurfaceSample>* out);

}  // namespace df::sim
