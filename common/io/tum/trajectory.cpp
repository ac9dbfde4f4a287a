#include "io/tum/trajectory.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "io/tum/stamp.hpp"
#include "io/tum/tum_folder.hpp"

namespace df::io {

namespace {

constexpr double kMaxStampS = 9223372036.0;  ///< int64 nanoseconds (year 2262)

bool parse_finite(const std::string& field, double* value) {
    if (field.empty()) return false;
    char* end = nullptr;
    errno = 0;
    *value = std::strtod(field.c_str(), &end);
    return end == field.c_str() + field.size() && errno != ERANGE && std::isfinite(*value);
}

/// Parses one data line; on failure returns what was wrong.
std::string parse_pose(const TumTextLine& line, StampReader* stamps, StampedPose* pose) {
    static const char* const kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    if (line.fields.size() < 8) {
        return "expected 'timestamp tx ty tz qx qy qz qw', found " +
               std::to_string(line.fields.size()) + " fields";
    }
    auto stamp = stamps->read(line.fields[0], line.line);
    if (!stamp) return stamp.status().message();
    // Exact nanoseconds to the nearest double: 0.24 us resolution at 1.3e9 s.
    pose->stamp_s = static_cast<double>(*stamp) / 1e9;
    double v[8] = {};
    for (int i = 1; i < 8; ++i) {
        if (!parse_finite(line.fields[i], &v[i])) {
            return std::string("expected a number for ") + kNames[i] + ", found '" +
                   line.fields[i] + "'";
        }
    }
    pose->t = Eigen::Vector3d(v[1], v[2], v[3]);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen takes w first
    if (q.norm() < 1e-6) return "quaternion qx qy qz qw is zero, expected a rotation";
    pose->q = q.normalized();
    return {};
}

}  // namespace

Result<TrajectoryParse> read_tum_trajectory(const std::string& file) {
    auto lines = read_tum_text_lines(file);
    if (!lines) return lines.status();
    TrajectoryParse parse;
    StampReader stamps;
    for (const TumTextLine& line : *lines) {
        StampedPose pose;
        const std::string what = parse_pose(line, &stamps, &pose);
        if (what.empty()) {
            parse.poses.push_back(pose);
        } else {
            parse.errors.push_back(file + ":" + std::to_string(line.line) + ": " + what);
        }
    }
    return parse;
}

Status write_tum_trajectory(const std::string& file, const std::vector<StampedPose>& poses) {
    std::string text =
        "# camera-to-world poses (world_T_camera)\n# timestamp tx ty tz qx qy qz qw\n";
    for (size_t i = 0; i < poses.size(); ++i) {
        const StampedPose& p = poses[i];
        const Eigen::Quaterniond q = p.q.normalized();
        const bool finite = std::isfinite(p.stamp_s) && p.t.allFinite() && q.coeffs().allFinite() &&
                            p.q.norm() > 1e-6;
        if (!finite || p.stamp_s < 0 || p.stamp_s > kMaxStampS) {
            return error(StatusCode::kInvalidArgument,
                         "cannot write " + file + ": pose " + std::to_string(i) +
                             " has a stamp outside [0, 9223372036] s, a non-finite value or a "
                             "zero quaternion");
        }
        char line[4096];  // room for any finite double in %f
        std::snprintf(line, sizeof line, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.stamp_s,
                      p.t.x() + 0.0, p.t.y() + 0.0, p.t.z() + 0.0,  // + 0.0: no "-0.000000000"
                      q.x() + 0.0, q.y() + 0.0, q.z() + 0.0, q.w() + 0.0);
        text += line;
    }
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + file);
    return Status::ok();
}

}  // namespace df::io
