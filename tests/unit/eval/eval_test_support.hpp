#pragma once
#include "temp_folder.hpp"
/// Helpers for the df_eval tests: a temporary folder, smooth synthetic trajectories, running
/// a command and reading JSON.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "eval/trajectory_metrics.hpp"

namespace df::eval::test {

using df::test::TempFolder;  // tests/support/temp_folder.hpp

inline void write_file(const std::string& path, const std::string& text) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    ASSERT_TRUE(out.good()) << "cannot write " << path;
}

/// A smooth 6-DoF motion (world_T_camera at time t): loops of about 3 m with turns of tens of
/// degrees, different extents along x, y, z.
inline io::StampedPose smooth_pose(double t) {
    io::StampedPose p;
    p.stamp_s = t;
    p.t = Eigen::Vector3d(1.5 * std::cos(0.4 * t), 0.3 * std::sin(0.9 * t),
                          0.8 * std::sin(0.4 * t) + 0.05 * t);
    p.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.2 * std::sin(0.7 * t), Eigen::Vector3d::UnitX()));
    return p;
}

/// Poses at t0 + i / rate_hz for i < count, stamps rounded to microseconds (as in files).
inline Trajectory smooth_trajectory(double t0, double rate_hz, int count) {
    Trajectory t;
    for (int i = 0; i < count; ++i) {
        t.push_back(smooth_pose(std::round((t0 + i / rate_hz) * 1e6) / 1e6));
    }
    return t;
}

inline io::StampedPose transformed(const Eigen::Isometry3d& T, const io::StampedPose& p) {
    io::StampedPose out = p;
    out.t = T * p.t;
    out.q = Eigen::Quaterniond(T.linear() * p.q.toRotationMatrix());
    return out;
}

inline Eigen::Isometry3d make_transform(double angle_rad, const Eigen::Vector3d& axis,
                                        const Eigen::Vector3d& t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
    T.translation() = t;
    return T;
}

/// Runs a shell command; returns its exit status and puts stdout+stderr in `output`.
inline int run_command(const std::string& command, std::string* output) {
    const std::string full = command + " 2>&1";
    FILE* pipe = ::popen(full.c_str(), "r");
    if (!pipe) return -1;
    char buffer[4096];
    output->clear();
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output->append(buffer, n);
    const int status = ::pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline nlohmann::json read_json(const std::string& file) {
    std::ifstream in(file);
    if (!in) return nlohmann::json();
    return nlohmann::json::parse(in, nullptr, false);
}

}  // namespace df::eval::test
