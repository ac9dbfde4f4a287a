#include "slam/depth_maps.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <vector>

// x86-64 builds target SSE2 only; the bilateral filter, most of preprocess's time, also has an
// AVX2 path chosen at run time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define DF_BILATERAL_AVX2 1
#else
#define DF_BILATERAL_AVX2 0
#endif

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

using Lanes = cv::v_float32x4;
constexpr int kLanes = Lanes::nlanes;

// exp(-q) for q = dz^2 / (2 sigma^2) in [0, 8] as 2^-n * 2^f (n integer, |f| <= 1/2), 2^f from a
// degree-4 near-minimax polynomial: relative error < 4e-6, so a filtered depth moves by less
// than 4 sigma * 4e-6 (< 1 um at sigma 3 cm) against std::exp. One std::exp per neighbour would
// cost more than all the rest of the filter.
inline Lanes exp2_neg(const Lanes& t) {  // 2^-t for t in [0, 12]
    const cv::v_int32x4 n = cv::v_round(t);
    const Lanes f = cv::v_cvt_f32(n) - t;
    Lanes p = cv::v_setall_f32(0.00966636837f);
    p = p * f + cv::v_setall_f32(0.0559219755f);
    p = p * f + cv::v_setall_f32(0.240223497f);
    p = p * f + cv::v_setall_f32(0.693121016f);
    p = p * f + cv::v_setall_f32(1.f);
    const cv::v_int32x4 bits = (cv::v_setall_s32(127) - n) << 23;
    return p * cv::v_reinterpret_as_f32(bits);
}

struct BilateralKernel {
    const cv::Mat* depth = nullptr;
    int radius = 0;
    std::vector<float> spatial;  // (2 radius + 1)^2 spatial weights, row-major
    float log2e_over_2s2 = 0.f;  // log2(e) / (2 sigma_depth^2)
    float cutoff_dz2 = 0.f;      // (4 sigma_depth)^2
    bool use_avx2 = false;       // 8 lanes per block where the CPU has them (same results)

    // Output columns [x, x + kLanes) of row y; every lane runs the same operations, so a pixel's
    // value does not depend on which lane or which thread computes it.
    // `rows` are the 2 radius + 1 input rows around y, each starting `radius` columns left of
    // the image, zero-padded on both sides.
    Lanes block(const float* const* rows, int x) const {
        const Lanes center = cv::v_load(rows[radius] + radius + x);
        const Lanes zero = cv::v_setzero_f32();
        const cv::v_uint32x4 center_valid = cv::v_reinterpret_as_u32(center > zero);
        if (!cv::v_check_any(center_valid)) return zero;
        const Lanes k = cv::v_setall_f32(log2e_over_2s2), cutoff = cv::v_setall_f32(cutoff_dz2);
        const Lanes t_max = cv::v_setall_f32(12.f);
        Lanes sum = zero, weight_sum = zero;
        const int side = 2 * radius + 1;
        for (int dy = 0; dy < side; ++dy) {
            const float* row = rows[dy] + x;
            const float* spatial_row = spatial.data() + dy * side;
            for (int dx = 0; dx < side; ++dx) {
                const Lanes z = cv::v_load(row + dx);
                const Lanes dz = z - center;
                const Lanes dz2 = dz * dz;
                // Invalid (0) neighbours and those beyond 4 sigma get weight 0; the clamp only
                // keeps 2^-t finite for them.
                const Lanes use = (z > zero) & (dz2 <= cutoff);
                const Lanes range = exp2_neg(cv::v_min(dz2 * k, t_max));
                const Lanes w = (cv::v_setall_f32(spatial_row[dx]) * range) & use;
                sum = sum + w * z;
                weight_sum = weight_sum + w;
            }
        }
        // A valid centre has weight 1 itself, so weight_sum > 0 wherever the quotient is kept.
        return cv::v_select(cv::v_reinterpret_as_f32(center_valid), sum / weight_sum, zero);
    }

#if DF_BILATERAL_AVX2
    // Output columns [0, x) of a row in blocks of 8 with AVX2; returns x, a multiple of 8.
    int avx2_blocks(const float* const* rows, int w, float* o) const;
#endif

    void filter_rows(const cv::Range& range, cv::Mat& out) const {
        const int w = out.cols, h = out.rows, side = 2 * radius + 1;
        // A ring of the last `side` input rows, zero-padded (invalid) by `radius` on the left and
        // up to a whole lane group plus `radius` on the right: each input row is copied once per
        // stripe, and the window needs no bounds checks.
        const int stride = w + 2 * radius + kLanes;
        std::vector<float> ring(static_cast<size_t>(side * stride), 0.f);
        std::vector<int> ring_row(static_cast<size_t>(side), -1);
        std::vector<const float*> rows(static_cast<size_t>(side));
        for (int y = range.start; y < range.end; ++y) {
            for (int dy = 0; dy < side; ++dy) {
                const int in_y = y + dy - radius;
                const int slot = (in_y + side) % side;  // in_y >= -radius
                float* row = ring.data() + slot * stride;
                if (ring_row[static_cast<size_t>(slot)] != in_y) {
                    ring_row[static_cast<size_t>(slot)] = in_y;
                    if (in_y < 0 || in_y >= h) {
                        std::fill(row, row + stride, 0.f);
                    } else {
                        const float* in = depth->ptr<float>(in_y);
                        std::copy(in, in + w, row + radius);  // the padding stays 0
                    }
                }
                rows[static_cast<size_t>(dy)] = row;
            }
            float* o = out.ptr<float>(y);
            int x = 0;
#if DF_BILATERAL_AVX2
            if (use_avx2) x = avx2_blocks(rows.data(), w, o);
#endif
            for (; x + kLanes <= w; x += kLanes) cv::v_store(o + x, block(rows.data(), x));
            if (x < w) {
                float tail[kLanes];
                cv::v_store(tail, block(rows.data(), x));
                std::copy(tail, tail + (w - x), o + x);
            }
        }
    }
};

#if DF_BILATERAL_AVX2
// BilateralKernel::block on 8 lanes: the same float operations in the same order (no FMA), so
// every pixel gets the same bits as on the 4-lane path.
__attribute__((target("avx2"))) int BilateralKernel::avx2_blocks(const float* const* rows, int w,
                                                                 float* o) const {
    const __m256 zero = _mm256_setzero_ps();
    const __m256 k = _mm256_set1_ps(log2e_over_2s2), cutoff = _mm256_set1_ps(cutoff_dz2);
    const __m256 t_max = _mm256_set1_ps(12.f);
    const int side = 2 * radius + 1;
    int x = 0;
    for (; x + 8 <= w; x += 8) {
        const __m256 center = _mm256_loadu_ps(rows[radius] + radius + x);
        const __m256 center_valid = _mm256_cmp_ps(center, zero, _CMP_GT_OQ);
        if (_mm256_movemask_ps(center_valid) == 0) {
            _mm256_storeu_ps(o + x, zero);
            continue;
        }
        __m256 sum = zero, weight_sum = zero;
        for (int dy = 0; dy < side; ++dy) {
            const float* row = rows[dy] + x;
            const float* spatial_row = spatial.data() + dy * side;
            for (int dx = 0; dx < side; ++dx) {
                const __m256 z = _mm256_loadu_ps(row + dx);
                const __m256 dz = _mm256_sub_ps(z, center);
                const __m256 dz2 = _mm256_mul_ps(dz, dz);
                const __m256 use = _mm256_and_ps(_mm256_cmp_ps(z, zero, _CMP_GT_OQ),
                                                 _mm256_cmp_ps(dz2, cutoff, _CMP_LE_OQ));
                const __m256 t = _mm256_min_ps(_mm256_mul_ps(dz2, k), t_max);
                // exp2_neg
                const __m256i n = _mm256_cvtps_epi32(t);
                const __m256 f = _mm256_sub_ps(_mm256_cvtepi32_ps(n), t);
                __m256 p = _mm256_set1_ps(0.00966636837f);
                p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(0.0559219755f));
                p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(0.240223497f));
                p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(0.693121016f));
                p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(1.f));
                const __m256i bits =
                    _mm256_slli_epi32(_mm256_sub_epi32(_mm256_set1_epi32(127), n), 23);
                const __m256 range = _mm256_mul_ps(p, _mm256_castsi256_ps(bits));
                const __m256 wgt =
                    _mm256_and_ps(_mm256_mul_ps(_mm256_set1_ps(spatial_row[dx]), range), use);
                sum = _mm256_add_ps(sum, _mm256_mul_ps(wgt, z));
                weight_sum = _mm256_add_ps(weight_sum, wgt);
            }
        }
        _mm256_storeu_ps(o + x, _mm256_and_ps(_mm256_div_ps(sum, weight_sum), center_valid));
    }
    return x;
}
#endif

}  // namespace

cv::Mat bilateral_filter_depth(const cv::Mat& depth_m, float sigma_space_px, float sigma_depth_m,
                               int radius_px) {
    CV_Assert(depth_m.type() == CV_32F && radius_px >= 0 && sigma_space_px > 0.f &&
              sigma_depth_m > 0.f);
    BilateralKernel kernel;
    kernel.radius = radius_px;
    const int side = 2 * radius_px + 1;
    kernel.spatial.resize(static_cast<size_t>(side * side));
    for (int dy = -radius_px; dy <= radius_px; ++dy) {
        for (int dx = -radius_px; dx <= radius_px; ++dx) {
            const float d2 = static_cast<float>(dx * dx + dy * dy);
            kernel.spatial[static_cast<size_t>((dy + radius_px) * side + dx + radius_px)] =
                std::exp(-d2 / (2.f * sigma_space_px * sigma_space_px));
        }
    }
    kernel.log2e_over_2s2 =
        static_cast<float>(1.4426950408889634 / 2.0 / (double{sigma_depth_m} * sigma_depth_m));
    kernel.cutoff_dz2 = 16.f * sigma_depth_m * sigma_depth_m;
#if DF_BILATERAL_AVX2
    kernel.use_avx2 = cv::checkHardwareSupport(CV_CPU_AVX2);
#endif
    kernel.depth = &depth_m;
    cv::Mat out(depth_m.size(), CV_32F);
    // Each output pixel depends on the input only, so any row split gives identical results.
    cv::parallel_for_(cv::Range(0, depth_m.rows),
                      [&](const cv::Range& rows) { kernel.filter_rows(rows, out); });
    return out;
}

namespace {

// One output row of downsample_depth, kLanes blocks at a time. Lanes past `w` read zeros (no
// valid pixel) from a copy and are dropped.
void downsample_row(const float* r0, const float* r1, int w, float max_diff_m, float* o) {
    const Lanes zero = cv::v_setzero_f32(), one = cv::v_setall_f32(1.f);
    const Lanes max_diff = cv::v_setall_f32(max_diff_m);
    for (int x = 0; x < w; x += kLanes) {
        Lanes tl, tr, bl, br;
        if (x + kLanes <= w) {
            cv::v_load_deinterleave(r0 + 2 * x, tl, tr);
            cv::v_load_deinterleave(r1 + 2 * x, bl, br);
        } else {
            float top[2 * kLanes] = {}, bottom[2 * kLanes] = {};
            std::copy(r0 + 2 * x, r0 + 2 * w, top);
            std::copy(r1 + 2 * x, r1 + 2 * w, bottom);
            cv::v_load_deinterleave(top, tl, tr);
            cv::v_load_deinterleave(bottom, bl, br);
        }
        // The reference is the first valid pixel; with none valid, no pixel is used below.
        const Lanes ref = cv::v_select(
            tl > zero, tl, cv::v_select(tr > zero, tr, cv::v_select(bl > zero, bl, br)));
        Lanes sum = zero, count = zero;
        for (const Lanes& z : {tl, tr, bl, br}) {
            const Lanes use = (z > zero) & (cv::v_abs(z - ref) <= max_diff);
            sum = sum + (z & use);
            count = count + (one & use);
        }
        const Lanes mean = cv::v_select(count > zero, sum / count, zero);
        if (x + kLanes <= w) {
            cv::v_store(o + x, mean);
        } else {
            float tail[kLanes];
            cv::v_store(tail, mean);
            std::copy(tail, tail + (w - x), o + x);
        }
    }
}

}  // namespace

cv::Mat downsample_depth(const cv::Mat& depth_m, float max_diff_m) {
    CV_Assert(depth_m.type() == CV_32F);
    cv::Mat out(depth_m.rows / 2, depth_m.cols / 2, CV_32F);
    cv::parallel_for_(cv::Range(0, out.rows), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            downsample_row(depth_m.ptr<float>(2 * y), depth_m.ptr<float>(2 * y + 1), out.cols,
                           max_diff_m, out.ptr<float>(y));
        }
    });
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

namespace {

struct Points {
    Lanes x, y, z;
};

// Back-projection of depth rows: the vertex of pixel (u, v) is (ray_x[u] z, ray_y(v) z, z), or
// (0,0,0) where z is not positive. Loads kLanes pixels at a time; those past the row's end read
// as invalid.
class DepthRays {
  public:
    DepthRays(const cv::Mat& depth_m, const io::Intrinsics& k) : depth_(depth_m), k_(k) {
        ray_x_.assign(static_cast<size_t>(depth_m.cols + kLanes), 0.f);
        for (int x = 0; x < depth_m.cols; ++x) {
            ray_x_[static_cast<size_t>(x)] = static_cast<float>((x - k.cx) / k.fx);
        }
    }

    Points load(int y, int x) const {
        const float* d = depth_.ptr<float>(y) + x;
        Lanes z;
        if (x + kLanes <= depth_.cols) {
            z = cv::v_load(d);
        } else {
            float tail[kLanes] = {};
            std::copy(d, d + (depth_.cols - x), tail);
            z = cv::v_load(tail);
        }
        const Lanes valid = z > cv::v_setzero_f32();
        const Lanes ray_y = cv::v_setall_f32(static_cast<float>((y - k_.cy) / k_.fy));
        // Masked after the products: ray * 0 would give -0 for rays left of or above centre.
        return {(cv::v_load(ray_x_.data() + x) * z) & valid, (ray_y * z) & valid, z & valid};
    }

  private:
    const cv::Mat& depth_;
    io::Intrinsics k_;
    std::vector<float> ray_x_;  // padded with kLanes zeros
};

// Points of a CV_32FC3 vertex map, kLanes at a time; those past the row's end read as (0,0,0).
class VertexPoints {
  public:
    explicit VertexPoints(const cv::Mat& vertex) : vertex_(vertex) {}

    Points load(int y, int x) const {
        const float* p = vertex_.ptr<float>(y) + 3 * x;
        Points out;
        if (x + kLanes <= vertex_.cols) {
            cv::v_load_deinterleave(p, out.x, out.y, out.z);
        } else {
            float tail[3 * kLanes] = {};
            std::copy(p, p + 3 * (vertex_.cols - x), tail);
            cv::v_load_deinterleave(tail, out.x, out.y, out.z);
        }
        return out;
    }

  private:
    const cv::Mat& vertex_;
};

// Stores the first min(kLanes, w - x) points at pixel x of a CV_32FC3 row.
void store_points(float* row, int x, int w, const Points& p) {
    if (x + kLanes <= w) {
        cv::v_store_interleave(row + 3 * x, p.x, p.y, p.z);
    } else {
        float tail[3 * kLanes];
        cv::v_store_interleave(tail, p.x, p.y, p.z);
        std::copy(tail, tail + 3 * (w - x), row + 3 * x);
    }
}

// Unit normals (dy x dx with dx = right - left, dy = down - up) oriented towards the camera,
// (0,0,0) where a point is invalid or the cross product vanishes. Every lane performs the float
// operations of the one-pixel formula in the same order (cross product, sqrt of the sum of
// squares left to right, times 1 / norm, sign of the dot product with mid), so results are
// bit-identical to it.
Points normals_of(const Points& left, const Points& right, const Points& up, const Points& down,
                  const Points& mid) {
    const Lanes zero = cv::v_setzero_f32();
    const Lanes invalid =
        (mid.z <= zero) | (left.z <= zero) | (right.z <= zero) | (up.z <= zero) | (down.z <= zero);
    const Lanes ax = down.x - up.x, ay = down.y - up.y, az = down.z - up.z;
    const Lanes bx = right.x - left.x, by = right.y - left.y, bz = right.z - left.z;
    Lanes nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const Lanes norm = cv::v_sqrt(nx * nx + ny * ny + nz * nz);
    const Lanes keep = (norm > cv::v_setall_f32(1e-12f)) & ~invalid;
    const Lanes inv_norm = cv::v_setall_f32(1.f) / norm;
    nx = nx * inv_norm;
    ny = ny * inv_norm;
    nz = nz * inv_norm;
    const Lanes flip = (nx * mid.x + ny * mid.y + nz * mid.z) > zero;
    const Lanes sign = flip & cv::v_setall_f32(-0.f);
    return {(nx ^ sign) & keep, (ny ^ sign) & keep, (nz ^ sign) & keep};
}

template <class Source>
cv::Mat normal_map(const Source& points, cv::Size size, int r) {
    cv::Mat out(size, CV_32FC3);
    const int w = size.width, h = size.height;
    cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            float* o = out.ptr<float>(y);
            if (y < r || y >= h - r || w < 2 * r + 1) {
                std::fill(o, o + 3 * w, 0.f);
                continue;
            }
            std::fill(o, o + 3 * r, 0.f);
            std::fill(o + 3 * (w - r), o + 3 * w, 0.f);
            // Pixels [x, x + kLanes) of [r, w - r); lanes past w - r - 1 are computed and
            // dropped.
            for (int x = r; x < w - r; x += kLanes) {
                const Points n =
                    normals_of(points.load(y, x - r), points.load(y, x + r), points.load(y - r, x),
                               points.load(y + r, x), points.load(y, x));
                store_points(o, x, w - r, n);
            }
        }
    });
    return out;
}

}  // namespace

cv::Mat compute_vertex_map(const cv::Mat& depth_m, const io::Intrinsics& k) {
    CV_Assert(depth_m.type() == CV_32F);
    const DepthRays rays(depth_m, k);
    cv::Mat out(depth_m.size(), CV_32FC3);
    cv::parallel_for_(cv::Range(0, depth_m.rows), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            for (int x = 0; x < depth_m.cols; x += kLanes) {
                store_points(out.ptr<float>(y), x, depth_m.cols, rays.load(y, x));
            }
        }
    });
    return out;
}

cv::Mat compute_normal_map(const cv::Mat& vertex, int baseline_px) {
    CV_Assert(vertex.type() == CV_32FC3 && baseline_px >= 1);
    return normal_map(VertexPoints(vertex), vertex.size(), baseline_px);
}

cv::Mat compute_normal_map(const cv::Mat& depth_m, const io::Intrinsics& k, int baseline_px) {
    CV_Assert(depth_m.type() == CV_32F && baseline_px >= 1);
    return normal_map(DepthRays(depth_m, k), depth_m.size(), baseline_px);
}

cv::Mat rgb_to_intensity(const cv::Mat& rgb) {
    CV_Assert(rgb.type() == CV_8UC3);
    cv::Mat out(rgb.size(), CV_32F);
    constexpr int kBytes = cv::v_uint8x16::nlanes;
    const Lanes wr = cv::v_setall_f32(0.299f), wg = cv::v_setall_f32(0.587f),
                wb = cv::v_setall_f32(0.114f);
    cv::parallel_for_(cv::Range(0, rgb.rows), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            const uint8_t* in = rgb.ptr<uint8_t>(y);
            float* o = out.ptr<float>(y);
            for (int x = 0; x < rgb.cols; x += kBytes) {
                const int n = std::min(kBytes, rgb.cols - x);
                uint8_t tail[3 * kBytes] = {};
                const uint8_t* p = in + 3 * x;
                if (n < kBytes) p = std::copy(p, p + 3 * n, tail) - 3 * n;
                cv::v_uint8x16 r, g, b;
                cv::v_load_deinterleave(p, r, g, b);
                float gray[kBytes];
                // 16 pixels as 4 x 4 floats, each 0.299 R + 0.587 G + 0.114 B left to right.
                cv::v_uint16x8 r16[2], g16[2], b16[2];
                cv::v_expand(r, r16[0], r16[1]);
                cv::v_expand(g, g16[0], g16[1]);
                cv::v_expand(b, b16[0], b16[1]);
                for (int half = 0; half < 2; ++half) {
                    cv::v_uint32x4 r32[2], g32[2], b32[2];
                    cv::v_expand(r16[half], r32[0], r32[1]);
                    cv::v_expand(g16[half], g32[0], g32[1]);
                    cv::v_expand(b16[half], b32[0], b32[1]);
                    for (int q = 0; q < 2; ++q) {
                        const Lanes value = wr * cv::v_cvt_f32(cv::v_reinterpret_as_s32(r32[q])) +
                                            wg * cv::v_cvt_f32(cv::v_reinterpret_as_s32(g32[q])) +
                                            wb * cv::v_cvt_f32(cv::v_reinterpret_as_s32(b32[q]));
                        cv::v_store(gray + (2 * half + q) * kLanes, value);
                    }
                }
                std::copy(gray, gray + n, o + x);
            }
        }
    });
    return out;
}

}  // namespace df::slam
