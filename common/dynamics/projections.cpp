#include "dynamics/projections.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

namespace df::dynamics {

namespace {

/// A vertex of the current camera (z > 0) moved into another camera and projected with the same
/// intrinsics: false when it lies behind that camera or outside its cols x rows image.
struct OtherCamera {
    OtherCamera(const Eigen::Isometry3f& other_T_current, float fx_, float fy_, float cx_,
                float cy_, cv::Size size)
        : r(other_T_current.linear()),
          t(other_T_current.translation()),
          fx(fx_),
          fy(fy_),
          cx(cx_),
          cy(cy_),
          cols(size.width),
          rows(size.height) {}
    Eigen::Matrix3f r;
    Eigen::Vector3f t;
    float fx, fy, cx, cy;
    int cols, rows;
    bool project(const cv::Vec3f& v, int* u, int* w, float* z) const {
        const Eigen::Vector3f q = r * Eigen::Vector3f(v[0], v[1], v[2]) + t;
        if (!(q.z() > 0.f)) return false;
        const float inv_z = 1.f / q.z();
        *u = cvRound(fx * q.x() * inv_z + cx);
        *w = cvRound(fy * q.y() * inv_z + cy);
        *z = q.z();
        return *u >= 0 && *w >= 0 && *u < cols && *w < rows;
    }
};

}  // namespace

cv::Mat warp_mask(const cv::Mat& previous, const cv::Mat& vertex,
                  const Eigen::Isometry3f& previous_T_current, float fx, float fy, float cx,
                  float cy, const cv::Mat& needed) {
    cv::Mat out = cv::Mat::zeros(vertex.size(), CV_8UC1);
    if (previous.empty() || previous.size() != vertex.size()) return out;
    const bool only_needed =
        !needed.empty() && needed.type() == CV_8UC1 && needed.size() == vertex.size();
    const OtherCamera previous_camera(previous_T_current, fx, fy, cx, cy, previous.size());
    cv::parallel_for_(cv::Range(0, vertex.rows), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            const cv::Vec3f* v = vertex.ptr<cv::Vec3f>(y);
            const uint8_t* n = only_needed ? needed.ptr<uint8_t>(y) : nullptr;
            uint8_t* o = out.ptr<uint8_t>(y);
            for (int x = 0; x < vertex.cols; ++x) {
                if (n && !n[x]) continue;
                if (!(v[x][2] > 0.f)) {
                    o[x] = previous.at<uint8_t>(y, x);
                    continue;
                }
                int u = 0, w = 0;
                float z = 0.f;
                if (previous_camera.project(v[x], &u, &w, &z)) o[x] = previous.at<uint8_t>(w, u);
            }
        }
    });
    return out;
}

cv::Mat history_evidence(const cv::Mat& vertex, const cv::Mat& residual_m, const cv::Mat& old_depth,
                         const cv::Mat& old_rigid, const Eigen::Isometry3f& old_T_current, float fx,
                         float fy, float cx, float cy, const params::slam::Motion& c,
                         const cv::Mat& needed) {
    cv::Mat out = cv::Mat::zeros(vertex.size(), CV_8UC1);
    if (old_depth.empty() || old_depth.type() != CV_32F || vertex.type() != CV_32FC3) return out;
    const bool only_needed =
        !needed.empty() && needed.type() == CV_8UC1 && needed.size() == vertex.size();
    const bool with_residual =
        !residual_m.empty() && residual_m.type() == CV_32F && residual_m.size() == vertex.size();
    const bool with_rigid =
        !old_rigid.empty() && old_rigid.type() == CV_8UC1 && old_rigid.size() == old_depth.size();
    const OtherCamera old_camera(old_T_current, fx, fy, cx, cy, old_depth.size());
    cv::parallel_for_(cv::Range(0, vertex.rows), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            const cv::Vec3f* v = vertex.ptr<cv::Vec3f>(y);
            const float* res = with_residual ? residual_m.ptr<float>(y) : nullptr;
            const uint8_t* n = only_needed ? needed.ptr<uint8_t>(y) : nullptr;
            uint8_t* o = out.ptr<uint8_t>(y);
            for (int x = 0; x < vertex.cols; ++x) {
                if (n && !n[x]) continue;
                int u = 0, w = 0;
                float z = 0.f;
                if (!(v[x][2] > 0.f) || !old_camera.project(v[x], &u, &w, &z)) continue;
                const float seen = old_depth.at<float>(w, u);
                if (!(seen > 0.f)) continue;
                const float split =
                    (res && std::isfinite(res[x]))
                        ? std::max(c.min_residual_m, c.history_split * std::fabs(res[x]))
                        : c.min_residual_m + c.min_residual_per_m2 * z * z;
                if (seen > z + split) {
                    o[x] = kMoved;
                } else if (seen >= z - split && (!with_rigid || old_rigid.at<uint8_t>(w, u))) {
                    o[x] = kStill;
                }
            }
        }
    });
    return out;
}

cv::Mat free_space_filled(const cv::Mat& vertex, const cv::Mat& old_depth,
                          const Eigen::Isometry3f& old_T_current, float fx, float fy, float cx,
                          float cy, const params::slam::Motion& c, const cv::Mat& candidates) {
    cv::Mat out = cv::Mat::zeros(vertex.size(), CV_8UC1);
    if (old_depth.empty() || old_depth.type() != CV_32F || vertex.type() != CV_32FC3) return out;
    const bool only_candidates =
        !candidates.empty() && candidates.type() == CV_8UC1 && candidates.size() == vertex.size();
    const OtherCamera old_camera(old_T_current, fx, fy, cx, cy, old_depth.size());
    const int last_u = old_depth.cols - 1, last_w = old_depth.rows - 1;
    const int step = std::max(1, c.seen_through_step_px);
    const int grid_rows = (vertex.rows + step - 1) / step;
    cv::parallel_for_(cv::Range(0, grid_rows), [&](const cv::Range& range) {
        for (int y = range.start * step; y < std::min(vertex.rows, range.end * step); y += step) {
            const cv::Vec3f* v = vertex.ptr<cv::Vec3f>(y);
            const uint8_t* n = only_candidates ? candidates.ptr<uint8_t>(y) : nullptr;
            for (int x = 0; x < vertex.cols; x += step) {
                if (n && !n[x]) continue;
                int u = 0, w = 0;
                float z = 0.f;
                if (!(v[x][2] > 0.f) || !old_camera.project(v[x], &u, &w, &z)) continue;
                if (u < 1 || w < 1 || u >= last_u || w >= last_w) continue;
                const float beyond =
                    z + c.seen_through_margin_m + c.seen_through_margin_per_m2 * z * z;
                // The centre first: on a static surface it is where almost every pixel stops.
                if (!(old_depth.at<float>(w, u) > beyond)) continue;
                bool through = true;
                for (int dw = -1; dw <= 1 && through; ++dw) {
                    const float* row = old_depth.ptr<float>(w + dw);
                    for (int du = -1; du <= 1 && through; ++du) through = row[u + du] > beyond;
                }
                if (!through) continue;
                // The sample stands for its step x step block (the candidates within it).
                for (int by = y; by < std::min(vertex.rows, y + step); ++by) {
                    const uint8_t* nb = only_candidates ? candidates.ptr<uint8_t>(by) : nullptr;
                    uint8_t* o = out.ptr<uint8_t>(by);
                    for (int bx = x; bx < std::min(vertex.cols, x + step); ++bx)
                        if (!nb || nb[bx]) o[bx] = 255;
                }
            }
        }
    });
    return out;
}

}  // namespace df::dynamics
