#include "sim/camera_path.hpp"

#include <cmath>

#include "sim/motion.hpp"
#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Matrix3d rot(const Vec3& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// Hand tremor: a few millimetres and a few tenths of a degree, smooth.
Iso3 tremor(const CameraPathConfig& c, double t) {
    Iso3 pose = Iso3::Identity();
    const double k = c.tremor;
    pose.translation() = 0.004 * k *
                         Vec3(wobble(c.seed, 101, t, 0.2, 1.5), wobble(c.seed, 102, t, 0.2, 1.5),
                              wobble(c.seed, 103, t, 0.2, 1.5));
    pose.linear() = rot(Vec3::UnitX(), 0.3 * kDeg * k * wobble(c.seed, 104, t, 0.2, 1.5)) *
                    rot(Vec3::UnitY(), 0.3 * kDeg * k * wobble(c.seed, 105, t, 0.2, 1.5)) *
                    rot(Vec3::UnitZ(), 0.2 * kDeg * k * wobble(c.seed, 106, t, 0.2, 1.5));
    return pose;
}

double sine(double t, double period_s, double phase) {
    return std::sin(2 * kPi * t / period_s + phase);
}

}  // namespace

const char* to_string(CameraMotion motion) {
    switch (motion) {
        case CameraMotion::kStatic:
            return "static";
        case CameraMotion::kXyz:
            return "xyz";
        case CameraMotion::kRpy:
            return "rpy";
        case CameraMotion::kHalfsphere:
            return "halfsphere";
        case CameraMotion::kHandheld:
            return "handheld";
    }
    return "static";
}

bool parse_camera_motion(const std::string& text, CameraMotion* motion) {
    for (CameraMotion m : {CameraMotion::kStatic, CameraMotion::kXyz, CameraMotion::kRpy,
                           CameraMotion::kHalfsphere, CameraMotion::kHandheld}) {
        if (text == to_string(m)) {
            *motion = m;
            return true;
        }
    }
    return false;
}

Iso3 look_at(const Vec3& position, const Vec3& target) {
    const Vec3 z = (target - position).normalized();
    Vec3 x = z.cross(Vec3::UnitZ());
    if (x.norm() < 1e-9) x = Vec3::UnitX();
    x.normalize();
    const Vec3 y = z.cross(x);
    Iso3 pose = Iso3::Identity();
    pose.linear() << x, y, z;
    pose.translation() = position;
    return pose;
}

Iso3 camera_pose(const CameraPathConfig& c, double t) {
    const double a = c.amplitude;
    const double p1 = 2 * kPi * hash01(c.seed, 201), p2 = 2 * kPi * hash01(c.seed, 202);
    const double p3 = 2 * kPi * hash01(c.seed, 203);
    const Iso3 nominal = look_at(c.position, c.target);
    Iso3 pose = nominal;
    switch (c.motion) {
        case CameraMotion::kStatic:
            break;
        case CameraMotion::kXyz: {
            const Vec3 offset_camera(0.22 * sine(t, 6.3, p1), 0.12 * sine(t, 4.7, p2),
                                     0.2 * sine(t, 8.9, p3));
            pose.translation() += nominal.linear() * (a * offset_camera);
            break;
        }
        case CameraMotion::kRpy: {
            pose.linear() = nominal.linear() *
                            rot(Vec3::UnitY(), a * 16 * kDeg * sine(t, 7.1, p1)) *
                            rot(Vec3::UnitX(), a * 10 * kDeg * sine(t, 5.3, p2)) *
                            rot(Vec3::UnitZ(), a * 12 * kDeg * sine(t, 4.1, p3));
            break;
        }
        case CameraMotion::kHalfsphere: {
            // Centre 0.5 m in front of the nominal position; the camera sweeps the half of the
            // sphere facing away from the scene, so at azimuth = elevation = 0 it is at `position`.
            const Vec3 forward = (c.target - c.position).normalized();
            const Vec3 centre = c.position + 0.5 * forward;
            const double az = a * 65 * kDeg * sine(t, 11.0, p1);
            const double el = a * 35 * kDeg * sine(t, 6.7, p2);
            const Eigen::Matrix3d r = nominal.linear();
            const Vec3 dir = r * (rot(Vec3::UnitY(), az) * rot(Vec3::UnitX(), el) * Vec3::UnitZ());
            const Vec3 position = centre - 0.5 * dir;
            pose = look_at(position, c.target);
            pose.linear() = pose.linear() * rot(Vec3::UnitZ(), 4 * kDeg * sine(t, 5.0, p3));
            break;
        }
        case CameraMotion::kHandheld: {
            const Eigen::Matrix3d r = nominal.linear();
            const Vec3 side = r.col(0), forward = (c.target - c.position).normalized();
            const Vec3 position = c.position + a * (1.0 * sine(t, 14.0, p1) * side +
                                                    0.35 * sine(t, 9.0, p2) * forward +
                                                    Vec3(0, 0, 0.1 * sine(t, 5.5, p3)));
            const Vec3 target = c.target + a * (0.6 * sine(t, 10.0, p2) * side +
                                                Vec3(0, 0, 0.25 * sine(t, 7.0, p1)));
            pose = look_at(position, target);
            pose.linear() = pose.linear() * rot(Vec3::UnitZ(), 5 * kDeg * sine(t, 6.0, p3));
            break;
        }
    }
    pose = pose * tremor(c, t);
    if (c.jump_at_s >= 0.0 && t >= c.jump_at_s) {
        pose.linear() = rot(Vec3::UnitZ(), c.jump_yaw_deg * kDeg) * pose.linear();
    }
    return pose;
}

}  // namespace df::sim
