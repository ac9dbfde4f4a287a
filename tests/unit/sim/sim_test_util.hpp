#pragma once
#include "temp_folder.hpp"
/// Helpers for the simulator tests: temporary folders, reading a generated sequence folder back
/// (independently of the generator's own code where it matters), nearest-point queries.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/rgbd_image.hpp"
#include "io/tum/trajectory.hpp"

namespace df::sim::test {

using df::test::TempFolder;  // tests/support/temp_folder.hpp

inline std::string read_text(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// A generated folder read back: stamps from associations.txt, intrinsics, poses.
struct SequenceFolder {
    std::string root;
    std::vector<std::string> stamps;  ///< file stems, in order
    io::Intrinsics k;
    int width = 0, height = 0;
    double units_per_m = 0;
    std::vector<Eigen::Isometry3d> world_T_camera;

    static SequenceFolder read(const std::string& root) {
        SequenceFolder f;
        f.root = root;
        std::istringstream assoc(read_text(root + "/associations.txt"));
        std::string line;
        while (std::getline(assoc, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream words(line);
            std::string t, rgb;
            words >> t >> rgb;
            f.stamps.push_back(t);
        }
        std::istringstream intr(read_text(root + "/intrinsics.txt"));
        while (std::getline(intr, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream words(line);
            words >> f.k.fx >> f.k.fy >> f.k.cx >> f.k.cy >> f.width >> f.height >> f.units_per_m;
        }
        f.world_T_camera = poses(root + "/groundtruth.txt");
        return f;
    }

    static std::vector<Eigen::Isometry3d> poses(const std::string& file) {
        std::vector<Eigen::Isometry3d> out;
        auto parsed = io::read_tum_trajectory(file);
        if (!parsed) return out;
        for (const auto& p : parsed->poses) {
            Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
            t.linear() = p.q.normalized().toRotationMatrix();
            t.translation() = p.t;
            out.push_back(t);
        }
        return out;
    }

    cv::Mat png(const std::string& folder, size_t i) const {
        return cv::imread(root + "/" + folder + "/" + stamps[i] + ".png", cv::IMREAD_UNCHANGED);
    }
    /// Depth in metres (CV_32F), 0 = invalid.
    cv::Mat depth_m(size_t i) const {
        cv::Mat raw = png("depth", i), m;
        raw.convertTo(m, CV_32F, 1.0 / units_per_m);
        return m;
    }
    Eigen::Vector3d back_project(int x, int y, double z) const {
        return Eigen::Vector3d((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
    }
};

/// Nearest-neighbour distances to a point set through a voxel hash (exact within `cell`).
class PointIndex {
  public:
    PointIndex(const std::vector<Eigen::Vector3d>& points, double cell)
        : cell_(cell), points_(points) {
        for (size_t i = 0; i < points_.size(); ++i) grid_[key(cell_of(points_[i]))].push_back(i);
    }
    /// Distance to the nearest point, or `cell` if none is within `cell`.
    double distance(const Eigen::Vector3d& q) const {
        const Eigen::Vector3i c = cell_of(q);
        double best = cell_ * cell_;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    auto it = grid_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
                    if (it == grid_.end()) continue;
                    for (size_t i : it->second)
                        best = std::min(best, (points_[i] - q).squaredNorm());
                }
        return std::sqrt(best);
    }

  private:
    Eigen::Vector3i cell_of(const Eigen::Vector3d& p) const {
        return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell_)),
                               static_cast<int>(std::floor(p.y() / cell_)),
                               static_cast<int>(std::floor(p.z() / cell_)));
    }
    static int64_t key(const Eigen::Vector3i& c) {
        return (static_cast<int64_t>(c.x()) * 73856093) ^ (static_cast<int64_t>(c.y()) * 19349663) ^
               (static_cast<int64_t>(c.z()) * 83492791);
    }
    double cell_;
    std::vector<Eigen::Vector3d> points_;
    std::unordered_map<int64_t, std::vector<size_t>> grid_;
};

/// p-quantile (0..1) of the values (copied); NaN for none.
inline double quantile(std::vector<double> v, double p) {
    if (v.empty()) return std::nan("");
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
}

}  // namespace df::sim::test
