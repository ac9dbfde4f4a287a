#include "sim/motion.hpp"

#include <algorithm>

#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap_pi(double a) {
    while (a > kPi) a -= 2 * kPi;
    while (a < -kPi) a += 2 * kPi;
    return a;
}

double smoothstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

/// Chaikin corner cutting with fixed end points.
std::vector<Vec2> round_corners(std::vector<Vec2> points, int iterations) {
    for (int it = 0; it < iterations && points.size() > 2; ++it) {
        std::vector<Vec2> next{points.front()};
        for (size_t i = 0; i + 1 < points.size(); ++i) {
            const Vec2 q = 0.75 * points[i] + 0.25 * points[i + 1];
            const Vec2 r = 0.25 * points[i] + 0.75 * points[i + 1];
            if (i > 0) next.push_back(q);
            if (i + 2 < points.size()) next.push_back(r);
        }
        next.push_back(points.back());
        points = std::move(next);
    }
    return points;
}

}  // namespace

Route::Route(const Vec2& start, double heading, double turn_rate_rad_s)
    : start_(start),
      end_(start),
      start_heading_(heading),
      end_heading_(heading),
      turn_rate_(turn_rate_rad_s) {}

void Route::add_turn(double heading, double seconds) {
    Leg leg;
    leg.kind = Leg::Kind::kTurn;
    leg.position = end_;
    leg.h0 = end_heading_;
    leg.h1 = end_heading_ + wrap_pi(heading - end_heading_);
    leg.turn_s = std::abs(leg.h1 - leg.h0) / turn_rate_;
    leg.t0 = t_end_;
    leg.t1 = t_end_ + std::max(seconds, leg.turn_s);
    leg.d0 = d_end_;
    end_heading_ = leg.h1;
    t_end_ = leg.t1;
    if (leg.t1 > leg.t0) legs_.push_back(leg);
}

Route& Route::move(const std::vector<Vec2>& waypoints, double speed_mps, double accel_mps2) {
    std::vector<Vec2> raw{end_};
    for (const Vec2& w : waypoints)
        if ((w - raw.back()).norm() > 1e-6) raw.push_back(w);
    if (raw.size() < 2) return *this;
    const Vec2 first_dir = raw[1] - raw[0];
    add_turn(std::atan2(first_dir.y(), first_dir.x()), 0.0);

    Leg leg;
    leg.kind = Leg::Kind::kMove;
    leg.points = round_corners(raw, 4);
    leg.cumulative.push_back(0);
    for (size_t i = 1; i < leg.points.size(); ++i)
        leg.cumulative.push_back(leg.cumulative.back() +
                                 (leg.points[i] - leg.points[i - 1]).norm());
    leg.length = leg.cumulative.back();
    // Vertex headings: the mean direction of the adjacent segments, unwrapped, starting from
    // the current heading so the turn before the move joins without a jump.
    double previous = end_heading_;
    for (size_t i = 0; i < leg.points.size(); ++i) {
        Vec2 dir = Vec2::Zero();
        if (i > 0) dir += (leg.points[i] - leg.points[i - 1]).normalized();
        if (i + 1 < leg.points.size()) dir += (leg.points[i + 1] - leg.points[i]).normalized();
        const double h = previous + wrap_pi(std::atan2(dir.y(), dir.x()) - previous);
        leg.headings.push_back(h);
        previous = h;
    }
    leg.accel = accel_mps2;
    if (leg.length < speed_mps * speed_mps / accel_mps2) {
        leg.v_peak = std::sqrt(leg.length * accel_mps2);
        leg.t_acc = leg.v_peak / accel_mps2;
        leg.t_cruise = 0;
    } else {
        leg.v_peak = speed_mps;
        leg.t_acc = speed_mps / accel_mps2;
        leg.t_cruise = (leg.length - speed_mps * leg.t_acc) / speed_mps;
    }
    leg.t0 = t_end_;
    leg.t1 = t_end_ + 2 * leg.t_acc + leg.t_cruise;
    leg.d0 = d_end_;
    legs_.push_back(leg);
    t_end_ = leg.t1;
    d_end_ += leg.length;
    end_ = leg.points.back();
    end_heading_ = leg.headings.back();
    return *this;
}

Route& Route::wait(double seconds, double heading) {
    add_turn(std::isnan(heading) ? end_heading_ : heading, seconds);
    return *this;
}

Route& Route::close_loop(double speed_mps, double period_s) {
    if ((end_ - start_).norm() > 1e-6) move({start_}, speed_mps);
    add_turn(start_heading_, 0.0);
    if (period_s > t_end_) add_turn(start_heading_, period_s - t_end_);
    loop_ = true;
    return *this;
}

Route::Sample Route::sample_leg(const Leg& leg, double t) const {
    Sample s;
    const double tau = std::clamp(t - leg.t0, 0.0, leg.t1 - leg.t0);
    if (leg.kind == Leg::Kind::kTurn) {
        s.position = leg.position;
        s.heading =
            leg.turn_s > 0 ? leg.h0 + (leg.h1 - leg.h0) * smoothstep(tau / leg.turn_s) : leg.h1;
        s.distance = leg.d0;
        return s;
    }
    const double total = leg.t1 - leg.t0;
    double dist, speed;
    if (tau < leg.t_acc) {
        dist = 0.5 * leg.accel * tau * tau;
        speed = leg.accel * tau;
    } else if (tau < leg.t_acc + leg.t_cruise) {
        dist = 0.5 * leg.accel * leg.t_acc * leg.t_acc + leg.v_peak * (tau - leg.t_acc);
        speed = leg.v_peak;
    } else {
        const double rest = std::max(0.0, total - tau);
        dist = leg.length - 0.5 * leg.accel * rest * rest;
        speed = leg.accel * rest;
    }
    dist = std::clamp(dist, 0.0, leg.length);
    const auto it = std::upper_bound(leg.cumulative.begin(), leg.cumulative.end(), dist);
    const size_t i = std::min<size_t>(std::max<ptrdiff_t>(it - leg.cumulative.begin(), 1),
                                      leg.points.size() - 1);
    const double seg = leg.cumulative[i] - leg.cumulative[i - 1];
    const double f = seg > 0 ? (dist - leg.cumulative[i - 1]) / seg : 0.0;
    s.position = leg.points[i - 1] + f * (leg.points[i] - leg.points[i - 1]);
    s.heading = leg.headings[i - 1] + f * (leg.headings[i] - leg.headings[i - 1]);
    s.speed = speed;
    s.distance = leg.d0 + dist;
    return s;
}

Route::Sample Route::at(double t_s) const {
    if (legs_.empty()) return {start_, start_heading_, 0, 0};
    double t = std::max(0.0, t_s);
    double distance_offset = 0, heading_offset = 0;
    if (loop_ && t_end_ > 0 && t >= t_end_) {
        const double loops = std::floor(t / t_end_);
        t -= loops * t_end_;
        distance_offset = loops * d_end_;
        heading_offset = loops * (end_heading_ - start_heading_);
    }
    auto it = std::upper_bound(legs_.begin(), legs_.end(), t,
                               [](double value, const Leg& leg) { return value < leg.t1; });
    if (it == legs_.end()) --it;
    Sample s = sample_leg(*it, t);
    s.distance += distance_offset;
    s.heading += heading_offset;
    return s;
}

ObjectState GroundMotion::at(double t_s) const {
    const Route::Sample s = route_.at(t_s);
    return {ground_pose(s.position.x(), s.position.y(), s.heading + yaw_offset_, z_), {}};
}

ObjectState RollingMotion::at(double t_s) const {
    const Route::Sample s = route_.at(t_s);
    Iso3 pose = ground_pose(s.position.x(), s.position.y(), s.heading, radius_);
    pose.linear() = pose.linear() * Eigen::AngleAxisd(s.distance / radius_, Vec3::UnitY());
    return {pose, {}};
}

double wobble(uint64_t seed, uint64_t channel, double t_s, double min_hz, double max_hz) {
    double sum = 0;
    for (uint64_t k = 0; k < 3; ++k) {
        const double hz = min_hz + (max_hz - min_hz) * hash01(seed, channel, k, 1);
        const double phase = 2 * kPi * hash01(seed, channel, k, 2);
        sum += std::sin(2 * kPi * hz * t_s + phase);
    }
    return sum / 2.0;
}

}  // namespace df::sim
