// Primitives, routes, bodies and camera paths: properties with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/camera_path.hpp"
#include "sim/motion.hpp"
#include "sim/person.hpp"
#include "sim/rng.hpp"
#include "sim/shapes.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Shape> test_shapes() {
    Iso3 tilted = Iso3::Identity();
    tilted.linear() = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    tilted.translation() = Vec3(0.1, -0.2, 0.3);
    return {make_box(Vec3(0.3, 0.2, 0.1), tilted, 0),
            make_ellipsoid(Vec3(0.2, 0, 0), Vec3(0.3, 0.2, 0.15), 0, tilted.linear()),
            make_frustum(Vec3(0, 0, -0.2), 0.25, Vec3(0.1, 0.1, 0.3), 0.1, 0),
            make_frustum(Vec3(-0.2, 0, 0), 0.15, Vec3(0.3, 0, 0), 0.15, 0),
            make_capsule(Vec3(-0.2, -0.1, 0), Vec3(0.3, 0.2, 0.1), 0.12, 0)};
}

/// Rays from outside the shape: a reported hit lies on the surface (inside just behind it,
/// outside just in front of it, along the surface normal), and no point before it is inside.
TEST(SimShapes, RayHitsLieOnTheSurfaceAndNothingIsInFront) {
    Rng rng(3);
    for (const Shape& shape : test_shapes()) {
        const Iso3 shape_T_parent = shape.parent_T_shape.inverse();
        int hits = 0;
        for (int i = 0; i < 400; ++i) {
            const Vec3 origin_parent =
                1.5 * Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
            const Vec3 aim(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
            const Vec3 o = shape_T_parent * origin_parent;
            const Vec3 d = shape_T_parent.linear() * (aim - origin_parent) * rng.uniform(0.5, 2.0);
            double t = 0;
            const bool hit = intersect(shape, o, d, 1e-9, 1e9, &t);
            const double t_end = hit ? t : 2.0;
            for (int k = 1; k < 100; ++k) {
                ASSERT_FALSE(contains(shape, o + (t_end * k / 100.0 * 0.999) * d))
                    << "a point before the reported hit is inside (type "
                    << static_cast<int>(shape.type) << ")";
            }
            if (!hit) continue;
            ++hits;
            const Vec3 p = o + t * d;
            const SurfacePoint s = surface_at(shape, p);
            EXPECT_NEAR(s.normal.norm(), 1.0, 1e-9);
            EXPECT_TRUE(contains(shape, p - 1e-5 * s.normal)) << static_cast<int>(shape.type);
            EXPECT_FALSE(contains(shape, p + 1e-5 * s.normal)) << static_cast<int>(shape.type);
            EXPECT_LT(s.normal.dot(d), 0) << "the ray must meet the outside of the surface";
        }
        EXPECT_GT(hits, 50) << static_cast<int>(shape.type);
    }
}

/// Surface samples lie on the surface, and every surface point found by a ray has a sample
/// within about the spacing.
TEST(SimShapes, SamplesCoverTheSurface) {
    const double spacing = 0.01;
    Rng rng(5);
    for (const Shape& shape : test_shapes()) {
        std::vector<SurfaceSample> samples;
        sample_surface(shape, spacing, 9, &samples);
        ASSERT_GT(samples.size(), 100u);
        for (const SurfaceSample& s : samples) {
            ASSERT_TRUE(contains(shape, s.p - 1e-5 * s.n));
            ASSERT_FALSE(contains(shape, s.p + 1e-5 * s.n));
        }
        double worst = 0;
        for (int i = 0; i < 300; ++i) {
            const Vec3 o = 2.0 * Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
            const Vec3 d = -o;
            double t;
            if (!intersect(shape, o, d, 0, 1e9, &t)) continue;
            const Vec3 p = o + t * d;
            double nearest = 1e9;
            for (const SurfaceSample& s : samples) nearest = std::min(nearest, (s.p - p).norm());
            worst = std::max(worst, nearest);
        }
        EXPECT_LT(worst, 1.2 * spacing) << "type " << static_cast<int>(shape.type);
    }
}

TEST(SimRoute, ReachesWaypointsStopsAndLoopsContinuously) {
    Route route(Vec2(0, 0), 0.0, 2.0);
    route.move({{2, 0}}, 1.0, 1.0)
        .wait(2.0, kPi / 2)
        .move({{2, 2}}, 1.0, 1.0)
        .close_loop(1.0, 20.0);
    EXPECT_NEAR(route.duration(), 20.0, 1e-9);
    // First move: 2 m at 1 m/s with 1 m/s^2 takes 3 s; then it stands still while turning.
    const Route::Sample at3 = route.at(3.0);
    EXPECT_NEAR((at3.position - Vec2(2, 0)).norm(), 0, 1e-6);
    EXPECT_NEAR(route.at(4.0).speed, 0, 1e-9);
    EXPECT_NEAR((route.at(4.0).position - Vec2(2, 0)).norm(), 0, 1e-9);
    EXPECT_NEAR(route.at(1.5).speed, 1.0, 1e-9);
    EXPECT_NEAR(route.at(3.0 + 2.0).heading, kPi / 2, 1e-6);
    // Continuity: no jumps between frames at 30 Hz, across loop boundaries too.
    Route::Sample previous = route.at(0);
    for (int i = 1; i < 30 * 45; ++i) {
        const Route::Sample s = route.at(i / 30.0);
        EXPECT_LT((s.position - previous.position).norm(), 1.5 / 30) << "t " << i / 30.0;
        // Turns follow a smoothstep: the peak rate is 1.5 times the mean turn rate (2 rad/s).
        EXPECT_LT(std::abs(s.heading - previous.heading), 1.5 * 2.0 / 30 + 1e-9)
            << "t " << i / 30.0;
        EXPECT_GE(s.distance, previous.distance);
        previous = s;
    }
    EXPECT_NEAR((route.at(20.0).position - Vec2(0, 0)).norm(), 0, 1e-6);
}

TEST(SimPerson, StandsOnTheFloorAndSwingsItsLimbsWhenWalking) {
    // Standing: the soles (foot ellipsoid bottoms) touch the floor.
    const std::vector<Iso3> bones = person_bones(BodyPose{});
    for (int foot : {kFootL, kFootR}) {
        const Vec3 sole = bones[foot] * Vec3(0.05, 0, -0.02 - 0.04);
        EXPECT_NEAR(sole.z(), 0.0, 1e-6);
    }
    Route route(Vec2(0, 0), 0.0);
    route.move({{10, 0}}, 1.2, 2.0);
    const WalkingPerson walker(route);
    double min_x = 1e9, max_x = -1e9;
    for (int i = 30; i < 150; ++i) {
        const ObjectState s = walker.at(i / 30.0);
        const Vec3 ankle = s.object_T_bone[kFootL].translation();
        min_x = std::min(min_x, ankle.x());
        max_x = std::max(max_x, ankle.x());
        EXPECT_GT(ankle.z(), -0.02);
    }
    EXPECT_GT(max_x - min_x, 0.4) << "the left foot swings back and forth relative to the body";
}

TEST(SimCameraPath, LooksAtTheTargetAndStaysNearTheNominalPose) {
    CameraPathConfig c;
    c.position = Vec3(0, -1, 1.5);
    c.target = Vec3(0, 2, 0.8);
    const Iso3 nominal = look_at(c.position, c.target);
    EXPECT_NEAR((nominal.linear().col(2) - (c.target - c.position).normalized()).norm(), 0, 1e-12);
    EXPECT_NEAR(nominal.linear().col(0).z(), 0, 1e-12) << "no roll: x stays horizontal";
    EXPECT_GT(nominal.linear().col(1).dot(Vec3(0, 0, -1)), 0) << "camera y points down";
    for (CameraMotion m : {CameraMotion::kStatic, CameraMotion::kXyz, CameraMotion::kRpy,
                           CameraMotion::kHalfsphere, CameraMotion::kHandheld}) {
        c.motion = m;
        double max_move = 0;
        for (int i = 0; i < 600; ++i) {
            const Iso3 pose = camera_pose(c, i / 30.0);
            max_move = std::max(max_move, (pose.translation() - c.position).norm());
            EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-9);
        }
        if (m == CameraMotion::kStatic || m == CameraMotion::kRpy) {
            EXPECT_LT(max_move, 0.02);
        }
        if (m == CameraMotion::kXyz) {
            EXPECT_GT(max_move, 0.15);
        }
        if (m == CameraMotion::kHalfsphere) {
            EXPECT_GT(max_move, 0.3);
            EXPECT_LT(max_move, 1.02);
        }
    }
}

}  // namespace
}  // namespace df::sim
