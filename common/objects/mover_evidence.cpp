#include "objects/mover_evidence.hpp"

#include <cmath>

namespace df::objects {

double mover_displacement_m(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                            const ObjectExtent& extent) {
    const double moved = ((b * extent.centroid) - (a * extent.centroid)).norm();
    const Eigen::AngleAxisd turn(Eigen::Matrix3d(a.linear().transpose() * b.linear()));
    return moved + std::fabs(turn.angle()) * extent.radius_m;
}

double mover_bound_m(double depth_m, const params::slam::Objects& c) {
    return c.mover_min_displacement_m + c.mover_displacement_per_m2 * depth_m * depth_m;
}

bool mover_settled(const MoverEvidence& e, const params::slam::Objects& c) {
    return !e.moving && e.frames_settled >= c.settle_after_frames;
}

bool update_mover(MoverEvidence* e, const Eigen::Isometry3d& world_T_object,
                  const ObjectExtent& extent, double depth_m, const params::slam::Objects& c) {
    if (!e->anchored) {
        e->anchored = true;
        e->anchor = world_T_object;
        e->still_since = world_T_object;
        return false;
    }
    const double bound = mover_bound_m(depth_m, c);
    if (!e->moving) {
        if (mover_displacement_m(e->anchor, world_T_object, extent) > bound) {
            e->frames_settled = 0;
            if (++e->frames_over >= c.mover_after_frames) {
                e->moving = true;
                ++e->times_proven;
                e->frames_over = 0;
                e->still_since = world_T_object;
                e->frames_within = 0;
                return true;
            }
        } else {
            e->frames_over = 0;
            ++e->frames_settled;
        }
        return false;
    }
    if (mover_displacement_m(e->still_since, world_T_object, extent) <= bound) {
        if (++e->frames_within >= c.still_after_frames) {
            e->moving = false;
            e->anchor = world_T_object;
            e->frames_over = 0;
            e->frames_settled = e->frames_within;  // it stood still that long
            e->frames_within = 0;
            return true;
        }
    } else {
        e->still_since = world_T_object;
        e->frames_within = 0;
    }
    return false;
}

}  // namespace df::objects
