#include "sim/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

bool pick_root(double t0, double t1, double t_min, double t_max, double* t) {
    if (t0 > t_min && t0 < t_max) {
        *t = t0;
        return true;
    }
    if (t1 > t_min && t1 < t_max) {
        *t = t1;
        return true;
    }
    return false;
}

/// Roots of a t^2 + 2 b t + c = 0 in ascending order; false if none are real.
bool half_b_roots(double a, double b, double c, double* t0, double* t1) {
    if (std::abs(a) < 1e-300) {
        if (std::abs(b) < 1e-300) return false;
        *t0 = *t1 = -c / (2 * b);
        return true;
    }
    const double disc = b * b - a * c;
    if (disc < 0) return false;
    const double s = std::sqrt(disc);
    // The numerically stable pair of roots.
    const double qq = b >= 0 ? -(b + s) : -(b - s);
    double r0 = qq / a, r1 = qq != 0 ? c / qq : r0;
    if (r0 > r1) std::swap(r0, r1);
    *t0 = r0;
    *t1 = r1;
    return true;
}

bool intersect_box(const Vec3& h, const Vec3& o, const Vec3& d, double t_min, double t_max,
                   double* t) {
    double t_near = -kInf, t_far = kInf;
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0) {
            if (std::abs(o[i]) > h[i]) return false;
            continue;
        }
        const double inv = 1.0 / d[i];
        double t0 = (-h[i] - o[i]) * inv, t1 = (h[i] - o[i]) * inv;
        if (t0 > t1) std::swap(t0, t1);
        t_near = std::max(t_near, t0);
        t_far = std::min(t_far, t1);
    }
    if (t_near > t_far) return false;
    return pick_root(t_near, t_far, t_min, t_max, t);
}

bool intersect_ellipsoid(const Vec3& r, const Vec3& o, const Vec3& d, double t_min, double t_max,
                         double* t) {
    const Vec3 os = o.cwiseQuotient(r), ds = d.cwiseQuotient(r);
    double t0, t1;
    if (!half_b_roots(ds.squaredNorm(), os.dot(ds), os.squaredNorm() - 1.0, &t0, &t1)) return false;
    return pick_root(t0, t1, t_min, t_max, t);
}

bool intersect_frustum(const Vec3& size, const Vec3& o, const Vec3& d, double t_min, double t_max,
                       double* t) {
    const double r0 = size.x(), r1 = size.y(), h = size.z();
    const double m = (r1 - r0) / (2 * h), q = 0.5 * (r0 + r1);
    double best = t_max;
    bool found = false;
    const double k0 = m * o.z() + q;
    double ta, tb;
    if (half_b_roots(d.x() * d.x() + d.y() * d.y() - m * m * d.z() * d.z(),
                     o.x() * d.x() + o.y() * d.y() - m * d.z() * k0,
                     o.x() * o.x() + o.y() * o.y() - k0 * k0, &ta, &tb)) {
        for (double tc : {ta, tb}) {
            if (tc <= t_min || tc >= best) continue;
            const double z = o.z() + tc * d.z();
            if (std::abs(z) <= h && m * z + q >= 0) {
                best = tc;
                found = true;
                break;
            }
        }
    }
    if (d.z() != 0) {
        for (double zc : {-h, h}) {
            const double tc = (zc - o.z()) / d.z();
            if (tc <= t_min || tc >= best) continue;
            const double x = o.x() + tc * d.x(), y = o.y() + tc * d.y();
            const double rc = zc > 0 ? r1 : r0;
            if (x * x + y * y <= rc * rc) {
                best = tc;
                found = true;
            }
        }
    }
    if (found) *t = best;
    return found;
}

bool intersect_capsule(const Vec3& size, const Vec3& o, const Vec3& d, double t_min, double t_max,
                       double* t) {
    const double r = size.x(), h = size.z();
    double best = t_max;
    bool found = false;
    double ta, tb;
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a > 1e-300 && half_b_roots(a, o.x() * d.x() + o.y() * d.y(),
                                   o.x() * o.x() + o.y() * o.y() - r * r, &ta, &tb)) {
        for (double tc : {ta, tb}) {
            if (tc <= t_min || tc >= best) continue;
            if (std::abs(o.z() + tc * d.z()) <= h) {
                best = tc;
                found = true;
                break;
            }
        }
    }
    for (double zc : {-h, h}) {
        const Vec3 oc(o.x(), o.y(), o.z() - zc);
        if (!half_b_roots(d.squaredNorm(), oc.dot(d), oc.squaredNorm() - r * r, &ta, &tb)) continue;
        for (double tc : {ta, tb}) {
            if (tc <= t_min || tc >= best) continue;
            best = tc;
            found = true;
            break;
        }
    }
    if (found) *t = best;
    return found;
}

}  // namespace

Eigen::Matrix3d frame_with_z(const Vec3& axis) {
    const Vec3 z = axis.normalized();
    const Vec3 helper = std::abs(z.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 y = z.cross(helper).normalized();
    const Vec3 x = y.cross(z);
    Eigen::Matrix3d r;
    r << x, y, z;
    return r;
}

Shape make_box(const Vec3& lo, const Vec3& hi, int material) {
    Shape s;
    s.type = ShapeType::kBox;
    s.size = 0.5 * (hi - lo).cwiseAbs();
    s.parent_T_shape = Iso3::Identity();
    s.parent_T_shape.translation() = 0.5 * (lo + hi);
    s.material = material;
    return s;
}

Shape make_box(const Vec3& half, const Iso3& parent_T_shape, int material) {
    Shape s;
    s.type = ShapeType::kBox;
    s.size = half;
    s.parent_T_shape = parent_T_shape;
    s.material = material;
    return s;
}

Shape make_ellipsoid(const Vec3& centre, const Vec3& radii, int material,
                     const Eigen::Matrix3d& rotation) {
    Shape s;
    s.type = ShapeType::kEllipsoid;
    s.size = radii;
    s.parent_T_shape = Iso3::Identity();
    s.parent_T_shape.linear() = rotation;
    s.parent_T_shape.translation() = centre;
    s.material = material;
    return s;
}

Shape make_frustum(const Vec3& p0, double r0, const Vec3& p1, double r1, int material) {
    Shape s;
    s.type = ShapeType::kFrustum;
    s.size = Vec3(r0, r1, 0.5 * (p1 - p0).norm());
    s.parent_T_shape = Iso3::Identity();
    s.parent_T_shape.linear() = frame_with_z(p1 - p0);
    s.parent_T_shape.translation() = 0.5 * (p0 + p1);
    s.material = material;
    return s;
}

Shape make_capsule(const Vec3& p0, const Vec3& p1, double radius, int material) {
    Shape s;
    s.type = ShapeType::kCapsule;
    s.size = Vec3(radius, radius, 0.5 * (p1 - p0).norm());
    s.parent_T_shape = Iso3::Identity();
    s.parent_T_shape.linear() = frame_with_z(p1 - p0);
    s.parent_T_shape.translation() = 0.5 * (p0 + p1);
    s.material = material;
    return s;
}

bool intersect(const Shape& shape, const Vec3& o, const Vec3& d, double t_min, double t_max,
               double* t) {
    switch (shape.type) {
        case ShapeType::kBox:
            return intersect_box(shape.size, o, d, t_min, t_max, t);
        case ShapeType::kEllipsoid:
            return intersect_ellipsoid(shape.size, o, d, t_min, t_max, t);
        case ShapeType::kFrustum:
            return intersect_frustum(shape.size, o, d, t_min, t_max, t);
        case ShapeType::kCapsule:
            return intersect_capsule(shape.size, o, d, t_min, t_max, t);
    }
    return false;
}

SurfacePoint surface_at(const Shape& shape, const Vec3& p) {
    SurfacePoint s;
    const Vec3& sz = shape.size;
    switch (shape.type) {
        case ShapeType::kBox: {
            int axis = 0;
            double best = -kInf;
            for (int i = 0; i < 3; ++i) {
                const double f = std::abs(p[i]) - sz[i];  // 0 on the face, negative inside
                if (f > best) {
                    best = f;
                    axis = i;
                }
            }
            const bool negative = p[axis] < 0;
            s.face = 2 * axis + (negative ? 1 : 0);
            s.normal = Vec3::Zero();
            s.normal[axis] = negative ? -1 : 1;
            const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
            s.u = p[ua] + sz[ua];
            s.v = p[va] + sz[va];
            s.u_extent = 2 * sz[ua];
            s.v_extent = 2 * sz[va];
            break;
        }
        case ShapeType::kEllipsoid: {
            s.normal = p.cwiseQuotient(sz.cwiseProduct(sz)).normalized();
            const double r = 0.5 * (sz.x() + sz.y());
            s.u = (std::atan2(p.y(), p.x()) + kPi) * r;
            s.v = p.z() + sz.z();
            s.u_extent = 2 * kPi * r;
            s.v_extent = 2 * sz.z();
            break;
        }
        case ShapeType::kFrustum: {
            const double h = sz.z(), m = (sz.y() - sz.x()) / (2 * h), q = 0.5 * (sz.x() + sz.y());
            const double rho = std::hypot(p.x(), p.y());
            const double r = m * p.z() + q;
            const double d_cap = h - std::abs(p.z());
            const double d_side = std::abs(rho - r) / std::sqrt(1 + m * m);
            const double rmax = std::max(sz.x(), sz.y());
            if (d_cap < d_side) {
                s.face = p.z() > 0 ? 1 : 2;
                s.normal = Vec3(0, 0, p.z() > 0 ? 1 : -1);
                s.u = p.x() + rmax;
                s.v = p.y() + rmax;
                s.u_extent = s.v_extent = 2 * rmax;
            } else {
                s.face = 0;
                s.normal = Vec3(p.x(), p.y(), -m * std::max(r, 0.0)).normalized();
                if (!std::isfinite(s.normal.x())) s.normal = Vec3::UnitX();
                s.u = (std::atan2(p.y(), p.x()) + kPi) * q;
                s.v = p.z() + h;
                s.u_extent = 2 * kPi * q;
                s.v_extent = 2 * h;
            }
            break;
        }
        case ShapeType::kCapsule: {
            const double r = sz.x(), h = sz.z();
            const double zc = std::clamp(p.z(), -h, h);
            s.normal = Vec3(p.x(), p.y(), p.z() - zc).normalized();
            if (!std::isfinite(s.normal.x())) s.normal = Vec3::UnitZ();
            s.u = (std::atan2(p.y(), p.x()) + kPi) * r;
            s.v = p.z() + h + r;
            s.u_extent = 2 * kPi * r;
            s.v_extent = 2 * (h + r);
            break;
        }
    }
    return s;
}

bool contains(const Shape& shape, const Vec3& p) {
    const Vec3& sz = shape.size;
    switch (shape.type) {
        case ShapeType::kBox:
            return std::abs(p.x()) < sz.x() && std::abs(p.y()) < sz.y() && std::abs(p.z()) < sz.z();
        case ShapeType::kEllipsoid:
            return p.cwiseQuotient(sz).squaredNorm() < 1.0;
        case ShapeType::kFrustum: {
            const double h = sz.z(), m = (sz.y() - sz.x()) / (2 * h), q = 0.5 * (sz.x() + sz.y());
            const double r = m * p.z() + q;
            return std::abs(p.z()) < h && r > 0 && p.x() * p.x() + p.y() * p.y() < r * r;
        }
        case ShapeType::kCapsule: {
            const double zc = std::clamp(p.z(), -sz.z(), sz.z());
            return Vec3(p.x(), p.y(), p.z() - zc).squaredNorm() < sz.x() * sz.x();
        }
    }
    return false;
}

Vec3 local_half_extents(const Shape& shape) {
    const Vec3& sz = shape.size;
    switch (shape.type) {
        case ShapeType::kBox:
        case ShapeType::kEllipsoid:
            return sz;
        case ShapeType::kFrustum: {
            const double r = std::max(sz.x(), sz.y());
            return Vec3(r, r, sz.z());
        }
        case ShapeType::kCapsule:
            return Vec3(sz.x(), sz.x(), sz.z() + sz.x());
    }
    return sz;
}

}  // namespace df::sim
