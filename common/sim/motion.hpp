#pragma once
/// Motions of things that move over the floor: a Route (walk or drive along waypoints, stop, turn,
/// go again) and rigid motions built on it (sliding, rolling).
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/scene.hpp"

namespace df::sim {

using Vec2 = Eigen::Vector2d;

/// A timed path on the floor (world x, y). Moves follow the waypoints with rounded corners and a
/// trapezoidal speed profile (start and end at rest); before a move the mover turns on the spot
/// to face the way it goes; waits may turn to a heading. Headings are radians about world z,
/// 0 = +x. Times are seconds from the start of the sequence.
class Route {
  public:
    static constexpr double kKeepHeading = std::numeric_limits<double>::quiet_NaN();

    /// turn_rate_rad_s: mean rate of turns on the spot (they ease in and out, peaking at 1.5x).
    Route(const Vec2& start, double heading, double turn_rate_rad_s = 2.0);
    /// Goes through the waypoints at up to speed_mps, accelerating at accel_mps2.
    Route& move(const std::vector<Vec2>& waypoints, double speed_mps, double accel_mps2 = 0.8);
    /// Stands still for `seconds`, turning to `heading` first if given.
    Route& wait(double seconds, double heading = kKeepHeading);
    /// Goes back to the start (at speed_mps), turns to the start heading, waits there until
    /// `period_s` (if longer; routes with one period keep their relative timing), and repeats.
    Route& close_loop(double speed_mps, double period_s = 0);

    struct Sample {
        Vec2 position = Vec2::Zero();
        double heading = 0;   ///< rad, continuous (not wrapped)
        double speed = 0;     ///< m/s along the path
        double distance = 0;  ///< metres travelled since t = 0
    };
    Sample at(double t_s) const;
    /// Time at which the route (one loop of it) ends.
    double duration() const { return t_end_; }

  private:
    struct Leg {
        enum class Kind { kMove, kTurn } kind = Kind::kTurn;
        double t0 = 0, t1 = 0, d0 = 0;
        // kTurn: position, heading h0 -> h1 over turn_s, then still until t1.
        Vec2 position = Vec2::Zero();
        double h0 = 0, h1 = 0, turn_s = 0;
        // kMove: rounded polyline with cumulative lengths and headings at the vertices.
        std::vector<Vec2> points;
        std::vector<double> cumulative, headings;
        double length = 0, v_peak = 0, accel = 1, t_acc = 0, t_cruise = 0;
    };
    Sample sample_leg(const Leg& leg, double t) const;
    void add_turn(double heading, double seconds);

    std::vector<Leg> legs_;
    Vec2 start_, end_;
    double start_heading_, end_heading_;
    double turn_rate_;
    double t_end_ = 0, d_end_ = 0;
    bool loop_ = false;
};

/// Slides over the floor along a route: world_T_object = ground pose at the route's position,
/// rotated by heading + yaw_offset, lifted by z.
class GroundMotion : public Motion {
  public:
    GroundMotion(Route route, double z = 0, double yaw_offset = 0)
        : route_(std::move(route)), z_(z), yaw_offset_(yaw_offset) {}
    ObjectState at(double t_s) const override;

  private:
    Route route_;
    double z_, yaw_offset_;
};

/// Rolls over the floor along a route without slipping: the object frame (origin at the centre,
/// its y axis the rolling axis, across the direction of travel) turns by distance / radius.
class RollingMotion : public Motion {
  public:
    RollingMotion(Route route, double radius) : route_(std::move(route)), radius_(radius) {}
    ObjectState at(double t_s) const override;

  private:
    Route route_;
    double radius_;
};

/// Never moves.
class FixedMotion : public Motion {
  public:
    explicit FixedMotion(const Iso3& world_T_object) : pose_(world_T_object) {}
    ObjectState at(double) const override { return {pose_, {}}; }

  private:
    Iso3 pose_;
};

/// Smooth pseudo-random signal in about [-1, 1]: three sines with seeded frequencies (between
/// min_hz and max_hz) and phases.
double wobble(uint64_t seed, uint64_t channel, double t_s, double min_hz = 0.05,
              double max_hz = 0.4);

}  // namespace df::sim
