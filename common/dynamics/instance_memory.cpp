#include "dynamics/instance_memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace df::dynamics {

std::string validate(const InstanceMemoryConfig& c) { return params::check(c); }

cv::Mat InstanceMemory::recall(const cv::Mat& vertex, const Eigen::Isometry3f& previous_T_current,
                               float fx, float fy, float cx, float cy,
                               const InstanceMemoryConfig& config) {
    cv::Mat out = cv::Mat::zeros(vertex.size(), CV_8UC1);
    recalled_ = cv::Mat::zeros(vertex.size(), CV_16UC1);
    if (config.frames <= 0 || depth_.empty() || depth_.size() != vertex.size()) return out;
    const Eigen::Matrix3f r = previous_T_current.linear();
    const Eigen::Vector3f t = previous_T_current.translation();
    for (int y = 0; y < vertex.rows; ++y) {
        const cv::Vec3f* v = vertex.ptr<cv::Vec3f>(y);
        uint8_t* o = out.ptr<uint8_t>(y);
        uint16_t* a = recalled_.ptr<uint16_t>(y);
        for (int x = 0; x < vertex.cols; ++x) {
            if (!(v[x][2] > 0.f)) continue;
            const Eigen::Vector3f q = r * Eigen::Vector3f(v[x][0], v[x][1], v[x][2]) + t;
            if (!(q.z() > 0.f)) continue;
            const float pu = fx * q.x() / q.z() + cx, pv = fy * q.y() / q.z() + cy;
            if (!(pu > -0.5f && pv > -0.5f && pu < depth_.cols - 0.5f && pv < depth_.rows - 0.5f))
                continue;
            const int u = static_cast<int>(std::lround(pu)), w = static_cast<int>(std::lround(pv));
            const float remembered = depth_.at<float>(w, u);
            if (!(remembered > 0.f)) continue;
            const int age = age_.at<uint16_t>(w, u);
            if (age + 1 > config.frames) continue;
            const float tolerance =
                config.max_depth_difference_m + config.max_depth_difference_per_m2 * q.z() * q.z();
            if (std::fabs(q.z() - remembered) > tolerance) continue;
            o[x] = 255;
            a[x] = static_cast<uint16_t>(age + 1);
        }
    }
    return out;
}

void InstanceMemory::store(const cv::Mat& detected, const cv::Mat& depth_m,
                           const InstanceMemoryConfig& config) {
    if (config.frames <= 0) {
        clear();
        return;
    }
    depth_ = cv::Mat::zeros(depth_m.size(), CV_32F);
    age_ = cv::Mat::zeros(depth_m.size(), CV_16UC1);
    const bool recalled = recalled_.size() == depth_m.size();
    for (int y = 0; y < depth_m.rows; ++y) {
        const float* z = depth_m.ptr<float>(y);
        const uint8_t* d = detected.empty() ? nullptr : detected.ptr<uint8_t>(y);
        const uint16_t* r = recalled ? recalled_.ptr<uint16_t>(y) : nullptr;
        float* out_z = depth_.ptr<float>(y);
        uint16_t* out_a = age_.ptr<uint16_t>(y);
        for (int x = 0; x < depth_m.cols; ++x) {
            if (!(z[x] > 0.f)) continue;
            if (d != nullptr && d[x] != 0) {
                out_z[x] = z[x];
            } else if (r != nullptr && r[x] != 0) {
                out_z[x] = z[x];
                out_a[x] = r[x];
            }
        }
    }
    recalled_.release();
}

void InstanceMemory::clear() {
    depth_.release();
    age_.release();
    recalled_.release();
}

int InstanceMemory::size() const { return depth_.empty() ? 0 : cv::countNonZero(depth_ > 0.f); }

}  // namespace df::dynamics
