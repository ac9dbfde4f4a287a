#include "slam/depth_maps.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace df::slam {

cv::Mat depth_to_metres(const cv::Mat& raw_depth, double units_per_m, float min_depth_m,
                        float max_depth_m) {
    cv::Mat out(raw_depth.size(), CV_32F);
    const float scale = static_cast<float>(1.0 / units_per_m);
    for (int y = 0; y < raw_depth.rows; ++y) {
        const uint16_t* in = raw_depth.ptr<uint16_t>(y);
        float* o = out.ptr<float>(y);
        for (int x = 0; x < raw_depth.cols; ++x) {
            const float z = static_cast<float>(in[x]) * scale;
            o[x] = (z >= min_depth_m && z < max_depth_m) ? z : 0.f;
        }
    }
    return out;
}

namespace {

// The depth weight exp(-dz^2 / 2 sigma^2) is read from a table: one exp per neighbour would
// dominate the frame time on a CPU. 64 bins per sigma keep the weight error below 1 %.
constexpr int kBinsPerSigma = 64;
constexpr int kSigmaCutoff = 4;
constexpr int kLutSize = kBinsPerSigma * kSigmaCutoff;

class BilateralRows : public cv::ParallelLoopBody {
  public:
    BilateralRows(const cv::Mat& in, cv::Mat& out, int radius, const std::vector<float>& spatial,
                  const std::array<float, kLutSize + 1>& lut, float inv_bin)
        : in_(in), out_(out), radius_(radius), spatial_(spatial), lut_(lut), inv_bin_(inv_bin) {}

    void operator()(const cv::Range& rows) const override {
        const int w = in_.cols, h = in_.rows, side = 2 * radius_ + 1;
        std::vector<float> sum(static_cast<size_t>(w)), weight_sum(static_cast<size_t>(w));
        const float last_bin = static_cast<float>(kLutSize);
        for (int y = rows.start; y < rows.end; ++y) {
            const float* center = in_.ptr<float>(y);
            std::fill(sum.begin(), sum.end(), 0.f);
            std::fill(weight_sum.begin(), weight_sum.end(), 0.f);
            const int dy0 = std::max(-radius_, -y), dy1 = std::min(radius_, h - 1 - y);
            // One window offset at a time over the whole row: no branches in the inner loop
            // (depth is noisy, so per-neighbour branches mispredict and cost more than the maths).
            for (int dy = dy0; dy <= dy1; ++dy) {
                const float* row = in_.ptr<float>(y + dy);
                for (int dx = -radius_; dx <= radius_; ++dx) {
                    const float spatial =
                        spatial_[static_cast<size_t>((dy + radius_) * side + dx + radius_)];
                    const int x0 = std::max(0, -dx), x1 = std::min(w, w - dx);
                    const float* neighbour = row + dx;
                    for (int x = x0; x < x1; ++x) {
                        const float z = neighbour[x];
                        const float bin = std::fmin(std::fabs(z - center[x]) * inv_bin_, last_bin);
                        const float valid = static_cast<float>(z > 0.f);
                        // lut_[kLutSize] == 0 cuts off beyond 4 sigma; invalid neighbours add 0.
                        const float wgt = valid * spatial * lut_[static_cast<int>(bin + 0.5f)];
                        sum[static_cast<size_t>(x)] += wgt * z;
                        weight_sum[static_cast<size_t>(x)] += wgt;
                    }
                }
            }
            float* o = out_.ptr<float>(y);
            for (int x = 0; x < w; ++x) {
                // A valid centre has weight 1 itself, so weight_sum > 0 there.
                o[x] = center[x] > 0.f
                           ? sum[static_cast<size_t>(x)] / weight_sum[static_cast<size_t>(x)]
                           : 0.f;
            }
        }
    }

  private:
    const cv::Mat& in_;
    cv::Mat& out_;
    int radius_;
    const std::vector<float>& spatial_;
    const std::array<float, kLutSize + 1>& lut_;
    float inv_bin_;
};

}  // namespace

cv::Mat bilateral_filter_depth(const cv::Mat& depth_m, float sigma_space_px, float sigma_depth_m,
                               int radius_px) {
    CV_Assert(depth_m.type() == CV_32F && radius_px >= 0 && sigma_space_px > 0.f &&
              sigma_depth_m > 0.f);
    const int side = 2 * radius_px + 1;
    std::vector<float> spatial(static_cast<size_t>(side * side));
    for (int dy = -radius_px; dy <= radius_px; ++dy) {
        for (int dx = -radius_px; dx <= radius_px; ++dx) {
            const float d2 = static_cast<float>(dx * dx + dy * dy);
            spatial[static_cast<size_t>((dy + radius_px) * side + dx + radius_px)] =
                std::exp(-d2 / (2.f * sigma_space_px * sigma_space_px));
        }
    }
    std::array<float, kLutSize + 1> lut{};
    for (int i = 0; i <= kLutSize; ++i) {
        const float s = static_cast<float>(i) / kBinsPerSigma;  // in units of sigma
        lut[static_cast<size_t>(i)] = std::exp(-0.5f * s * s);
    }
    lut[kLutSize] = 0.f;  // the cut-off: neighbours 4 sigma or more away do not count
    cv::Mat out(depth_m.size(), CV_32F);
    const float inv_bin = static_cast<float>(kBinsPerSigma) / sigma_depth_m;
    // Each output pixel depends on the input only, so any row split gives identical results.
    cv::parallel_for_(cv::Range(0, depth_m.rows),
                      BilateralRows(depth_m, out, radius_px, spatial, lut, inv_bin));
    return out;
}

cv::Mat downsample_depth(const cv::Mat& depth_m, float max_diff_m) {
    CV_Assert(depth_m.type() == CV_32F);
    cv::Mat out(depth_m.rows / 2, depth_m.cols / 2, CV_32F);
    for (int y = 0; y < out.rows; ++y) {
        const float* r0 = depth_m.ptr<float>(2 * y);
        const float* r1 = depth_m.ptr<float>(2 * y + 1);
        float* o = out.ptr<float>(y);
        for (int x = 0; x < out.cols; ++x) {
            const float block[4] = {r0[2 * x], r0[2 * x + 1], r1[2 * x], r1[2 * x + 1]};
            float ref = 0.f;
            for (float z : block) {
                if (z > 0.f) {
                    ref = z;
                    break;
                }
            }
            float sum = 0.f;
            int count = 0;
            if (ref > 0.f) {
                for (float z : block) {
                    if (z > 0.f && std::fabs(z - ref) <= max_diff_m) {
                        sum += z;
                        ++count;
                    }
                }
            }
            o[x] = count > 0 ? sum / static_cast<float>(count) : 0.f;
        }
    }
    return out;
}

io::Intrinsics scale_intrinsics(const io::Intrinsics& k, int level) {
    const double s = 1.0 / static_cast<double>(1 << level);
    io::Intrinsics out;
    out.fx = k.fx * s;
    out.fy = k.fy * s;
    out.cx = (k.cx + 0.5) * s - 0.5;
    out.cy = (k.cy + 0.5) * s - 0.5;
    return out;
}

cv::Mat compute_vertex_map(const cv::Mat& depth_m, const io::Intrinsics& k) {
    CV_Assert(depth_m.type() == CV_32F);
    std::vector<float> ray_x(static_cast<size_t>(depth_m.cols));
    for (int x = 0; x < depth_m.cols; ++x) {
        ray_x[static_cast<size_t>(x)] = static_cast<float>((x - k.cx) / k.fx);
    }
    cv::Mat out(depth_m.size(), CV_32FC3);
    for (int y = 0; y < depth_m.rows; ++y) {
        const float ray_y = static_cast<float>((y - k.cy) / k.fy);
        const float* d = depth_m.ptr<float>(y);
        cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
        for (int x = 0; x < depth_m.cols; ++x) {
            const float z = d[x];
            o[x] = z > 0.f ? cv::Vec3f(ray_x[static_cast<size_t>(x)] * z, ray_y * z, z)
                           : cv::Vec3f(0.f, 0.f, 0.f);
        }
    }
    return out;
}

cv::Mat compute_normal_map(const cv::Mat& vertex) {
    CV_Assert(vertex.type() == CV_32FC3);
    cv::Mat out(vertex.size(), CV_32FC3, cv::Scalar::all(0));
    for (int y = 1; y + 1 < vertex.rows; ++y) {
        const cv::Vec3f* up = vertex.ptr<cv::Vec3f>(y - 1);
        const cv::Vec3f* mid = vertex.ptr<cv::Vec3f>(y);
        const cv::Vec3f* down = vertex.ptr<cv::Vec3f>(y + 1);
        cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
        for (int x = 1; x + 1 < vertex.cols; ++x) {
            if (mid[x][2] <= 0.f || mid[x - 1][2] <= 0.f || mid[x + 1][2] <= 0.f ||
                up[x][2] <= 0.f || down[x][2] <= 0.f) {
                continue;
            }
            const cv::Vec3f dx = mid[x + 1] - mid[x - 1];
            const cv::Vec3f dy = down[x] - up[x];
            cv::Vec3f n = dy.cross(dx);
            const float norm = std::sqrt(n.dot(n));
            if (!(norm > 1e-12f)) continue;
            n *= 1.f / norm;
            if (n.dot(mid[x]) > 0.f) n = -n;
            o[x] = n;
        }
    }
    return out;
}

cv::Mat rgb_to_intensity(const cv::Mat& rgb) {
    CV_Assert(rgb.type() == CV_8UC3);
    cv::Mat out(rgb.size(), CV_32F);
    for (int y = 0; y < rgb.rows; ++y) {
        const uint8_t* in = rgb.ptr<uint8_t>(y);
        float* o = out.ptr<float>(y);
        for (int x = 0; x < rgb.cols; ++x) {
            o[x] = 0.299f * in[3 * x] + 0.587f * in[3 * x + 1] + 0.114f * in[3 * x + 2];
        }
    }
    return out;
}

}  // namespace df::slam
