// Surface sampling of the primitives (ground-truth models): jittered strata, deterministic.
#include <algorithm>
#include <cmath>

#include "sim/rng.hpp"
#include "sim/shapes.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Fibonacci points on the unit sphere (z from z_lo to 1), n of them.
void fibonacci_cap(int n, double z_lo, double phase, std::vector<Vec3>* out) {
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < n; ++k) {
        const double z = 1.0 - (1.0 - z_lo) * (k + 0.5) / n;
        const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = k * golden + phase;
        out->emplace_back(rho * std::cos(phi), rho * std::sin(phi), z);
    }
}

/// Jittered rings on a disc of radius `radius` at height z with normal (0, 0, nz).
void sample_disc(double radius, double z, double nz, double spacing, Rng* rng,
                 std::vector<SurfaceSample>* out) {
    if (radius <= 0) return;
    const int rings = std::max(1, static_cast<int>(std::ceil(radius / spacing)));
    for (int k = 0; k < rings; ++k) {
        const double rho = (k + rng->uniform(0.2, 0.8)) * radius / rings;
        const int n = std::max(1, static_cast<int>(std::ceil(2 * kPi * rho / spacing)));
        const double phase = rng->uniform(0, 2 * kPi);
        for (int i = 0; i < n; ++i) {
            const double a = phase + 2 * kPi * (i + rng->uniform(0.2, 0.8)) / n;
            out->push_back({Vec3(rho * std::cos(a), rho * std::sin(a), z), Vec3(0, 0, nz)});
        }
    }
}

/// Jittered rings on the side of a frustum (radius r0 at z=-h .. r1 at z=+h).
void sample_side(double r0, double r1, double h, double spacing, Rng* rng,
                 std::vector<SurfaceSample>* out) {
    const double m = (r1 - r0) / (2 * h), q = 0.5 * (r0 + r1);
    const double slant = std::sqrt(4 * h * h + (r1 - r0) * (r1 - r0));
    const int rings = std::max(1, static_cast<int>(std::ceil(slant / spacing)));
    for (int j = 0; j < rings; ++j) {
        const double z = -h + 2 * h * (j + rng->uniform(0.2, 0.8)) / rings;
        const double r = m * z + q;
        if (r <= 0) continue;
        const int n = std::max(3, static_cast<int>(std::ceil(2 * kPi * r / spacing)));
        const double phase = rng->uniform(0, 2 * kPi);
        for (int i = 0; i < n; ++i) {
            const double a = phase + 2 * kPi * (i + rng->uniform(0.2, 0.8)) / n;
            const Vec3 p(r * std::cos(a), r * std::sin(a), z);
            out->push_back({p, Vec3(p.x(), p.y(), -m * r).normalized()});
        }
    }
}

}  // namespace

void sample_surface(const Shape& shape, double spacing, uint64_t seed,
                    std::vector<SurfaceSample>* out) {
    Rng rng(seed);
    const Vec3& sz = shape.size;
    switch (shape.type) {
        case ShapeType::kBox: {
            for (int axis = 0; axis < 3; ++axis) {
                const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
                const int nu = std::max(1, static_cast<int>(std::ceil(2 * sz[ua] / spacing)));
                const int nv = std::max(1, static_cast<int>(std::ceil(2 * sz[va] / spacing)));
                for (double sign : {1.0, -1.0}) {
                    Vec3 n = Vec3::Zero();
                    n[axis] = sign;
                    for (int i = 0; i < nu; ++i) {
                        for (int j = 0; j < nv; ++j) {
                            Vec3 p;
                            p[axis] = sign * sz[axis];
                            p[ua] = -sz[ua] + 2 * sz[ua] * (i + rng.uniform(0.2, 0.8)) / nu;
                            p[va] = -sz[va] + 2 * sz[va] * (j + rng.uniform(0.2, 0.8)) / nv;
                            out->push_back({p, n});
                        }
                    }
                }
            }
            break;
        }
        case ShapeType::kEllipsoid: {
            // Counted for the largest radius, so the stretched direction is not under-sampled.
            const double rmax = sz.maxCoeff();
            const int n = std::max(
                4, static_cast<int>(std::ceil(4 * kPi * rmax * rmax / (spacing * spacing))));
            std::vector<Vec3> unit;
            fibonacci_cap(n, -1.0, rng.uniform(0, 2 * kPi), &unit);
            for (const Vec3& u : unit) {
                const Vec3 p = u.cwiseProduct(sz);
                out->push_back({p, p.cwiseQuotient(sz.cwiseProduct(sz)).normalized()});
            }
            break;
        }
        case ShapeType::kFrustum:
            sample_side(sz.x(), sz.y(), sz.z(), spacing, &rng, out);
            sample_disc(sz.y(), sz.z(), 1.0, spacing, &rng, out);
            sample_disc(sz.x(), -sz.z(), -1.0, spacing, &rng, out);
            break;
        case ShapeType::kCapsule: {
            const double r = sz.x(), h = sz.z();
            sample_side(r, r, h, spacing, &rng, out);
            const int n =
                std::max(2, static_cast<int>(std::ceil(2 * kPi * r * r / (spacing * spacing))));
            for (double sign : {1.0, -1.0}) {
                std::vector<Vec3> unit;
                fibonacci_cap(n, 0.0, rng.uniform(0, 2 * kPi), &unit);
                for (const Vec3& u : unit) {
                    const Vec3 n_local(u.x(), u.y(), sign * u.z());
                    out->push_back({Vec3(0, 0, sign * h) + r * n_local, n_local});
                }
            }
            break;
        }
    }
}

}  // namespace df::sim
