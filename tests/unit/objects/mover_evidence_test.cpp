// A detected object is a candidate mover until its own tracked poses show it moving beyond the
// bound that depth noise and tracking error explain (objects/mover_evidence.hpp).
#include "objects/mover_evidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "objects/object_maps.hpp"

namespace df::objects {
namespace {

Eigen::Isometry3d at(double x, double yaw = 0) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(x, 2.0, 0.0);
    p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return p;
}

ObjectExtent extent() {
    ObjectExtent e;
    e.centroid = Eigen::Vector3d(0, 0, 0.2);
    e.radius_m = 0.3;
    return e;
}

TEST(MoverEvidence, DisplacementCountsTranslationAndTurnAtTheRadius) {
    EXPECT_NEAR(mover_displacement_m(at(0), at(0.05), extent()), 0.05, 1e-9);
    // A turn in place about z through the centroid's axis moves the surface by angle x radius.
    EXPECT_NEAR(mover_displacement_m(at(0), at(0, 0.1), extent()), 0.1 * 0.3, 1e-9);
}

TEST(MoverEvidence, TrackingNoiseOnAStillObjectNeverProvesMotion) {
    ObjectMapsConfig c;
    MoverEvidence e;
    std::mt19937 rng(7);
    // Tracking noise of a few millimetres and a tenth of a degree, at 1.5 m, for 600 frames.
    std::normal_distribution<double> noise(0.0, 0.004), turn(0.0, 0.002);
    for (int i = 0; i < 600; ++i) {
        update_mover(&e, at(noise(rng), turn(rng)), extent(), 1.5, c);
        ASSERT_FALSE(e.moving) << "frame " << i;
    }
    EXPECT_EQ(e.times_proven, 0);
}

TEST(MoverEvidence, AMoverIsProvenAfterEnoughFramesAndIsStillAgainWhenItStops) {
    ObjectMapsConfig c;
    MoverEvidence e;
    update_mover(&e, at(0), extent(), 1.5, c);  // anchors
    // 1 cm a frame: beyond the bound (3 cm + 0.5 cm x 1.5^2 = 4.1 cm) from frame 5 on, proven
    // mover_after_frames tracked frames later.
    int proven_at = -1;
    for (int i = 1; i <= 30 && proven_at < 0; ++i) {
        update_mover(&e, at(0.01 * i), extent(), 1.5, c);
        if (e.moving) proven_at = i;
    }
    ASSERT_GT(proven_at, 0);
    EXPECT_EQ(proven_at, 4 + c.mover_after_frames);
    // It stops: still again after still_after_frames tracked frames within the bound.
    int still_after = 0;
    while (e.moving && still_after < 1000) {
        update_mover(&e, at(0.3), extent(), 1.5, c);
        ++still_after;
    }
    // (The first frame at the stop is still a step beyond the bound.)
    EXPECT_EQ(still_after, c.still_after_frames + 1);
    EXPECT_FALSE(e.moving);
    // Anchored where it stopped: standing there proves nothing.
    for (int i = 0; i < 50; ++i) update_mover(&e, at(0.3), extent(), 1.5, c);
    EXPECT_FALSE(e.moving);
}

TEST(MoverEvidence, ACandidateSettlesOnlyAfterEnoughStillFramesAndAMoverNever) {
    ObjectMapsConfig c;
    MoverEvidence still;
    update_mover(&still, at(0), extent(), 1.5, c);  // anchors
    int settled_at = -1;
    for (int i = 1; i <= 100 && settled_at < 0; ++i) {
        update_mover(&still, at(0.002 * (i % 2)), extent(), 1.5, c);
        if (mover_settled(still, c)) settled_at = i;
    }
    EXPECT_EQ(settled_at, c.settle_after_frames);
    // A frame beyond the bound unsettles it: settled again only after as many still frames.
    update_mover(&still, at(0.2), extent(), 1.5, c);
    EXPECT_FALSE(mover_settled(still, c));
    EXPECT_FALSE(still.moving);
    // A mover from its first frames never settles while it moves ...
    MoverEvidence mover;
    for (int i = 0; i < 60; ++i) {
        update_mover(&mover, at(0.02 * i), extent(), 1.5, c);
        ASSERT_FALSE(mover_settled(mover, c)) << "frame " << i;
    }
    EXPECT_TRUE(mover.moving);
    // ... and is settled as soon as it is still again (it stood still_after_frames).
    for (int i = 0; i < c.still_after_frames + 1 && mover.moving; ++i)
        update_mover(&mover, at(2.0), extent(), 1.5, c);
    EXPECT_FALSE(mover.moving);
    EXPECT_TRUE(mover_settled(mover, c));
}

TEST(MoverEvidence, TheBoundGrowsWithDepthSquared) {
    ObjectMapsConfig c;
    EXPECT_NEAR(mover_bound_m(0.0, c), c.mover_min_displacement_m, 1e-9);
    EXPECT_NEAR(mover_bound_m(3.0, c) - mover_bound_m(0.0, c), 9 * c.mover_displacement_per_m2,
                1e-9);
    // 4 cm steps away from the camera at 4 m are within the noise (3 + 8 cm): not proven.
    MoverEvidence e;
    for (int i = 0; i < 3; ++i) update_mover(&e, at(0.04 * (i % 2)), extent(), 4.0, c);
    EXPECT_FALSE(e.moving);
}

}  // namespace
}  // namespace df::objects
