#include "slam/tracker_terms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "slam/depth_maps.hpp"

namespace df::slam::tracker_detail {

namespace {

// Rows per block of the parallel accumulation. Blocks are fixed by the image size alone and
// reduced in block order, so the sums do not depend on how many threads ran them.
constexpr int kBlockRows = 8;
// Pixels are accumulated in groups of kLanes independent float sums (the compiler maps them to
// SIMD registers), flushed to double once per row.
constexpr int kLanes = 8;

// Depth tolerance of the model's 2x2 block average: the frame pyramid's default, so the two
// pyramids treat discontinuities alike.
const float kModelPyramidMaxDiffM = PreprocessConfig{}.pyramid_max_depth_diff_m;

// A pyrDown output is usable only when (nearly) all of its 5x5 support was valid.
constexpr float kMinSupport = 0.999f;

inline float huber_weight(float r, float threshold) {
    const float a = std::fabs(r);
    return a <= threshold ? 1.f : threshold / a;
}

// The rows (Jacobian, residual, weight) of one image row's contributing pixels, structure of
// arrays, so that the normal equations are summed with vector instructions.
class RowBuffer {
  public:
    explicit RowBuffer(int width)
        : capacity_((width + kLanes - 1) / kLanes * kLanes),
          data_(static_cast<size_t>(8 * capacity_), 0.f) {}

    void push(const float j[6], float r, float weight) {
        for (int c = 0; c < 6; ++c) column(c)[size_] = j[c];
        column(6)[size_] = r;
        column(7)[size_] = weight;
        ++size_;
    }

    // Adds weight J^T J and weight J^T r of the buffered rows to `eq` and empties the buffer.
    void flush(NormalEquations& eq) {
        if (size_ == 0) return;
        const int padded = (size_ + kLanes - 1) / kLanes * kLanes;
        for (int i = size_; i < padded; ++i) column(7)[i] = 0.f;  // padding contributes 0
        float acc[27][kLanes] = {};
        const float* __restrict j0 = column(0);
        const float* __restrict j1 = column(1);
        const float* __restrict j2 = column(2);
        const float* __restrict j3 = column(3);
        const float* __restrict j4 = column(4);
        const float* __restrict j5 = column(5);
        const float* __restrict r = column(6);
        const float* __restrict w = column(7);
        // Written out so that each line is one vector multiply-add over the kLanes lanes.
        for (int base = 0; base < padded; base += kLanes) {
            for (int k = 0; k < kLanes; ++k) {
                const int i = base + k;
                const float a0 = j0[i], a1 = j1[i], a2 = j2[i], a3 = j3[i], a4 = j4[i], a5 = j5[i];
                const float w0 = w[i] * a0, w1 = w[i] * a1, w2 = w[i] * a2, w3 = w[i] * a3,
                            w4 = w[i] * a4, w5 = w[i] * a5;
                acc[0][k] += w0 * a0;
                acc[1][k] += w0 * a1;
                acc[2][k] += w0 * a2;
                acc[3][k] += w0 * a3;
                acc[4][k] += w0 * a4;
                acc[5][k] += w0 * a5;
                acc[6][k] += w1 * a1;
                acc[7][k] += w1 * a2;
                acc[8][k] += w1 * a3;
                acc[9][k] += w1 * a4;
                acc[10][k] += w1 * a5;
                acc[11][k] += w2 * a2;
                acc[12][k] += w2 * a3;
                acc[13][k] += w2 * a4;
                acc[14][k] += w2 * a5;
                acc[15][k] += w3 * a3;
                acc[16][k] += w3 * a4;
                acc[17][k] += w3 * a5;
                acc[18][k] += w4 * a4;
                acc[19][k] += w4 * a5;
                acc[20][k] += w5 * a5;
                acc[21][k] += w0 * r[i];
                acc[22][k] += w1 * r[i];
                acc[23][k] += w2 * r[i];
                acc[24][k] += w3 * r[i];
                acc[25][k] += w4 * r[i];
                acc[26][k] += w5 * r[i];
            }
        }
        for (int idx = 0; idx < 27; ++idx) {
            double sum = 0.0;
            for (int k = 0; k < kLanes; ++k) sum += static_cast<double>(acc[idx][k]);
            if (idx < 21) {
                eq.a[static_cast<size_t>(idx)] += sum;
            } else {
                eq.b[static_cast<size_t>(idx - 21)] += sum;
            }
        }
        size_ = 0;
    }

  private:
    float* column(int c) { return data_.data() + static_cast<size_t>(c * capacity_); }

    int capacity_;
    std::vector<float> data_;
    int size_ = 0;
};

// Runs `kernel(first_row, end_row, eq)` over fixed blocks of the `rows` rows in parallel and
// sums the blocks in order.
template <typename Kernel>
NormalEquations reduce_row_blocks(int rows, const Kernel& kernel) {
    const int blocks = (rows + kBlockRows - 1) / kBlockRows;
    std::vector<NormalEquations> partial(static_cast<size_t>(blocks));
    cv::parallel_for_(cv::Range(0, blocks), [&](const cv::Range& range) {
        for (int b = range.start; b < range.end; ++b) {
            kernel(b * kBlockRows, std::min(rows, (b + 1) * kBlockRows),
                   partial[static_cast<size_t>(b)]);
        }
    });
    NormalEquations total;
    for (const NormalEquations& p : partial) total.add(p);
    return total;
}

void downsample_vertex_normal(const cv::Mat& vertex, const cv::Mat& normal, cv::Mat& vertex_out,
                              cv::Mat& normal_out) {
    vertex_out.create(vertex.rows / 2, vertex.cols / 2, CV_32FC3);
    normal_out.create(vertex_out.size(), CV_32FC3);
    for (int y = 0; y < vertex_out.rows; ++y) {
        const cv::Vec3f* v_rows[2] = {vertex.ptr<cv::Vec3f>(2 * y), vertex.ptr<cv::Vec3f>(2 * y + 1)};
        const cv::Vec3f* n_rows[2] = {normal.ptr<cv::Vec3f>(2 * y), normal.ptr<cv::Vec3f>(2 * y + 1)};
        cv::Vec3f* vo = vertex_out.ptr<cv::Vec3f>(y);
        cv::Vec3f* no = normal_out.ptr<cv::Vec3f>(y);
        for (int x = 0; x < vertex_out.cols; ++x) {
            const cv::Vec3f* vs[4] = {&v_rows[0][2 * x], &v_rows[0][2 * x + 1], &v_rows[1][2 * x],
                                      &v_rows[1][2 * x + 1]};
            const cv::Vec3f* ns[4] = {&n_rows[0][2 * x], &n_rows[0][2 * x + 1], &n_rows[1][2 * x],
                                      &n_rows[1][2 * x + 1]};
            float ref = 0.f;
            for (const cv::Vec3f* v : vs) {
                if ((*v)[2] > 0.f) {
                    ref = (*v)[2];
                    break;
                }
            }
            cv::Vec3f v_sum(0.f, 0.f, 0.f), n_sum(0.f, 0.f, 0.f);
            int v_count = 0, n_count = 0;
            if (ref > 0.f) {
                for (int k = 0; k < 4; ++k) {
                    if ((*vs[k])[2] > 0.f && std::fabs((*vs[k])[2] - ref) <= kModelPyramidMaxDiffM) {
                        v_sum += *vs[k];
                        ++v_count;
                        if (is_valid_normal(*ns[k])) {
                            n_sum += *ns[k];
                            ++n_count;
                        }
                    }
                }
            }
            vo[x] = v_count > 0 ? v_sum * (1.f / static_cast<float>(v_count)) : cv::Vec3f();
            const float n_norm = std::sqrt(n_sum.dot(n_sum));
            no[x] = (n_count > 0 && n_norm > 1e-6f) ? n_sum * (1.f / n_norm) : cv::Vec3f();
        }
    }
}

// Gaussian pyrDown of an intensity image whose unusable pixels are negative, normalised by the
// valid support (so holes do not darken their neighbours).
cv::Mat downsample_intensity(const cv::Mat& intensity, cv::Size size) {
    cv::Mat masked(intensity.size(), CV_32F), support(intensity.size(), CV_32F);
    for (int y = 0; y < intensity.rows; ++y) {
        const float* in = intensity.ptr<float>(y);
        float* m = masked.ptr<float>(y);
        float* s = support.ptr<float>(y);
        for (int x = 0; x < intensity.cols; ++x) {
            const bool ok = in[x] >= 0.f;
            m[x] = ok ? in[x] : 0.f;
            s[x] = ok ? 1.f : 0.f;
        }
    }
    cv::Mat num, den;
    cv::pyrDown(masked, num, size);
    cv::pyrDown(support, den, size);
    for (int y = 0; y < num.rows; ++y) {
        float* n = num.ptr<float>(y);
        const float* d = den.ptr<float>(y);
        for (int x = 0; x < num.cols; ++x) n[x] = d[x] >= kMinSupport ? n[x] / d[x] : -1.f;
    }
    return num;
}

}  // namespace

void NormalEquations::add(const NormalEquations& other) {
    for (size_t i = 0; i < a.size(); ++i) a[i] += other.a[i];
    for (size_t i = 0; i < b.size(); ++i) b[i] += other.b[i];
    agreeing += other.agreeing;
    residual_sq += other.residual_sq;
    weighted_sq += other.weighted_sq;
    used += other.used;
}

std::vector<ModelLevel> build_model_pyramid(const ModelView& model, int levels,
                                            bool with_intensity) {
    std::vector<ModelLevel> out(static_cast<size_t>(levels));
    out[0].vertex = model.vertex;
    out[0].normal = model.normal;
    if (with_intensity) {
        out[0].intensity = rgb_to_intensity(model.colour);
        for (int y = 0; y < model.vertex.rows; ++y) {
            const cv::Vec3f* v = model.vertex.ptr<cv::Vec3f>(y);
            float* i = out[0].intensity.ptr<float>(y);
            for (int x = 0; x < model.vertex.cols; ++x) {
                if (!is_valid_vertex(v[x])) i[x] = -1.f;
            }
        }
    }
    for (size_t l = 1; l < out.size(); ++l) {
        downsample_vertex_normal(out[l - 1].vertex, out[l - 1].normal, out[l].vertex,
                                 out[l].normal);
        if (with_intensity) {
            out[l].intensity = downsample_intensity(out[l - 1].intensity, out[l].vertex.size());
        }
    }
    return out;
}

std::vector<cv::Mat> build_mask_pyramid(const cv::Mat& mask, int levels) {
    std::vector<cv::Mat> out(static_cast<size_t>(levels));
    if (mask.empty()) return out;
    out[0] = mask;
    for (size_t l = 1; l < out.size(); ++l) {
        const cv::Mat& in = out[l - 1];
        cv::Mat m(in.rows / 2, in.cols / 2, CV_8UC1);
        for (int y = 0; y < m.rows; ++y) {
            const uint8_t* r0 = in.ptr<uint8_t>(2 * y);
            const uint8_t* r1 = in.ptr<uint8_t>(2 * y + 1);
            uint8_t* o = m.ptr<uint8_t>(y);
            for (int x = 0; x < m.cols; ++x) {
                o[x] = (r0[2 * x] | r0[2 * x + 1] | r1[2 * x] | r1[2 * x + 1]) ? 255 : 0;
            }
        }
        out[l] = m;
    }
    return out;
}

NormalEquations accumulate_icp(const FrameLevel& frame, const cv::Mat& mask, int step,
                               const ModelLevel& model, const PoseF& pose,
                               const TrackingConfig& config, int& valid) {
    const io::Intrinsics& k = frame.intrinsics;
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    const float max_u = static_cast<float>(model.vertex.cols) - 0.5f;
    const float max_v = static_cast<float>(model.vertex.rows) - 0.5f;
    const float max_d2 = config.icp_max_distance_m * config.icp_max_distance_m;
    const float max_sin2 = config.icp_max_normal_sin * config.icp_max_normal_sin;
    const float agree_m = config.inlier_residual_m;
    const float huber = config.icp_huber_m;
    const float max_z = config.max_depth_m > 0.f ? config.max_depth_m
                                                 : std::numeric_limits<float>::infinity();
    const float* R = pose.r;
    const float* t = pose.t;
    const int width = frame.width(), stepped_rows = (frame.height() + step - 1) / step;
    // Raw pointers and strides hoisted out of the pixel loop (cv::Mat members would be reloaded
    // after every store).
    const uint8_t* const model_vertex = model.vertex.data;
    const uint8_t* const model_normal = model.normal.data;
    const size_t vertex_stride = model.vertex.step[0], normal_stride = model.normal.step[0];
    std::vector<int> valid_per_block((stepped_rows + kBlockRows - 1) / kBlockRows, 0);
    NormalEquations total = reduce_row_blocks(stepped_rows, [&](int row0, int row1,
                                                                  NormalEquations& eq) {
        RowBuffer rows((width + step - 1) / step);
        int block_valid = 0;
        for (int sy = row0; sy < row1; ++sy) {
            const int y = sy * step;
            const cv::Vec3f* fv = frame.vertex.ptr<cv::Vec3f>(y);
            const cv::Vec3f* fn = frame.normal.ptr<cv::Vec3f>(y);
            const uint8_t* m = mask.empty() ? nullptr : mask.ptr<uint8_t>(y);
            for (int x = 0; x < width; x += step) {
                const cv::Vec3f& p = fv[x];
                const cv::Vec3f& n = fn[x];
                if (!(p[2] > 0.f) || !(p[2] <= max_z) || !is_valid_normal(n) || (m && m[x])) {
                    continue;
                }
                const float qx = R[0] * p[0] + R[1] * p[1] + R[2] * p[2] + t[0];
                const float qy = R[3] * p[0] + R[4] * p[1] + R[5] * p[2] + t[1];
                const float qz = R[6] * p[0] + R[7] * p[1] + R[8] * p[2] + t[2];
                if (!(qz > 0.f)) continue;
                const float inv_z = 1.f / qz;
                const float u = fx * qx * inv_z + cx, v = fy * qy * inv_z + cy;
                if (!(u > -0.5f && u < max_u && v > -0.5f && v < max_v)) continue;
                const int ui = static_cast<int>(u + 0.5f), vi = static_cast<int>(v + 0.5f);
                const float* mv = reinterpret_cast<const float*>(
                                      model_vertex + static_cast<size_t>(vi) * vertex_stride) +
                                  3 * ui;
                if (!(mv[2] > 0.f) || !(mv[2] <= max_z)) continue;
                const float* mn = reinterpret_cast<const float*>(
                                      model_normal + static_cast<size_t>(vi) * normal_stride) +
                                  3 * ui;
                if (mn[0] == 0.f && mn[1] == 0.f && mn[2] == 0.f) continue;
                // The inlier ratio counts over the pixels that land on the model: a model that
                // covers part of the view (new ground, confident surfels only) is no failure.
                ++block_valid;
                const float dx = qx - mv[0], dy = qy - mv[1], dz = qz - mv[2];
                if (dx * dx + dy * dy + dz * dz > max_d2) continue;
                const float nx = R[0] * n[0] + R[1] * n[1] + R[2] * n[2];
                const float ny = R[3] * n[0] + R[4] * n[1] + R[5] * n[2];
                const float nz = R[6] * n[0] + R[7] * n[1] + R[8] * n[2];
                if (nx * mn[0] + ny * mn[1] + nz * mn[2] <= 0.f) continue;
                const float r = mn[0] * dx + mn[1] * dy + mn[2] * dz;
                eq.agreeing += std::fabs(r) <= agree_m ? 1 : 0;
                const float sx = ny * mn[2] - nz * mn[1], sy2 = nz * mn[0] - nx * mn[2],
                            sz = nx * mn[1] - ny * mn[0];
                if (sx * sx + sy2 * sy2 + sz * sz > max_sin2) continue;
                // d r / d t = n_model, d r / d w = q x n_model.
                const float j[6] = {mn[0],
                                    mn[1],
                                    mn[2],
                                    qy * mn[2] - qz * mn[1],
                                    qz * mn[0] - qx * mn[2],
                                    qx * mn[1] - qy * mn[0]};
                const float hw = huber_weight(r, huber);
                rows.push(j, r, hw);
                eq.residual_sq += static_cast<double>(r) * r;
                eq.weighted_sq += static_cast<double>(hw) * r * r;
                ++eq.used;
            }
            rows.flush(eq);
        }
        valid_per_block[static_cast<size_t>(row0 / kBlockRows)] = block_valid;
    });
    valid = 0;
    for (int v : valid_per_block) valid += v;
    return total;
}

NormalEquations accumulate_rgb(const ModelLevel& model, int step, const FrameLevel& frame,
                               const cv::Mat& mask, const PoseF& camera_T_reference,
                               const PoseF& reference_T_camera, float min_gradient,
                               const TrackingConfig& config) {
    const io::Intrinsics& k = frame.intrinsics;
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    const float max_u = static_cast<float>(frame.width() - 1);
    const float max_v = static_cast<float>(frame.height() - 1);
    const float min_grad2 = min_gradient * min_gradient;
    const float max_dz = config.rgb_max_depth_difference_m;
    const float huber = config.rgb_huber;
    const float max_z = config.max_depth_m > 0.f ? config.max_depth_m
                                                 : std::numeric_limits<float>::infinity();
    const float* Rc = camera_T_reference.r;
    const float* tc = camera_T_reference.t;
    const float* Rr = reference_T_camera.r;
    const int width = model.vertex.cols, stepped_rows = (model.vertex.rows + step - 1) / step;
    return reduce_row_blocks(stepped_rows, [&](int row0, int row1, NormalEquations& eq) {
        RowBuffer rows((width + step - 1) / step);
        for (int sy = row0; sy < row1; ++sy) {
            const int my = sy * step;
            const cv::Vec3f* mv = model.vertex.ptr<cv::Vec3f>(my);
            const float* mi = model.intensity.ptr<float>(my);
            for (int mx = 0; mx < width; mx += step) {
                const cv::Vec3f& p = mv[mx];
                if (!(p[2] > 0.f) || !(p[2] <= max_z) || mi[mx] < 0.f) continue;
                const float x = Rc[0] * p[0] + Rc[1] * p[1] + Rc[2] * p[2] + tc[0];
                const float y = Rc[3] * p[0] + Rc[4] * p[1] + Rc[5] * p[2] + tc[1];
                const float z = Rc[6] * p[0] + Rc[7] * p[1] + Rc[8] * p[2] + tc[2];
                if (!(z > 0.f)) continue;
                const float inv_z = 1.f / z;
                const float u = fx * x * inv_z + cx, v = fy * y * inv_z + cy;
                // Bilinear sampling needs the 2x2 neighbourhood inside the image.
                if (!(u >= 0.f && u < max_u && v >= 0.f && v < max_v)) continue;
                const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
                const float ax = u - static_cast<float>(x0), ay = v - static_cast<float>(y0);
                const int xn = x0 + (ax >= 0.5f ? 1 : 0), yn = y0 + (ay >= 0.5f ? 1 : 0);
                if (!mask.empty() && mask.ptr<uint8_t>(yn)[xn]) continue;
                const float depth = frame.depth_m.ptr<float>(yn)[xn];
                if (!(depth > 0.f) || std::fabs(depth - z) > max_dz) continue;
                const float w00 = (1.f - ax) * (1.f - ay), w10 = ax * (1.f - ay);
                const float w01 = (1.f - ax) * ay, w11 = ax * ay;
                const auto sample = [&](const cv::Mat& image) {
                    const float* r0 = image.ptr<float>(y0) + x0;
                    const float* r1 = image.ptr<float>(y0 + 1) + x0;
                    return w00 * r0[0] + w10 * r0[1] + w01 * r1[0] + w11 * r1[1];
                };
                const float gx = sample(frame.grad_x), gy = sample(frame.grad_y);
                if (gx * gx + gy * gy < min_grad2) continue;
                const float r = sample(frame.intensity) - mi[mx];
                // d r / d p' (current camera frame): image gradient times the projection
                // Jacobian.
                const float gu = gx * fx * inv_z, gv = gy * fy * inv_z;
                const float g[3] = {gu, gv, -(gu * x + gv * y) * inv_z};
                // The same gradient in the reference frame; p' = R^T (v - t) moves by
                // -R^T (w x v + t) under the increment, so d r / d t = -h and d r / d w = h x v.
                const float hx = Rr[0] * g[0] + Rr[1] * g[1] + Rr[2] * g[2];
                const float hy = Rr[3] * g[0] + Rr[4] * g[1] + Rr[5] * g[2];
                const float hz = Rr[6] * g[0] + Rr[7] * g[1] + Rr[8] * g[2];
                const float j[6] = {-hx,
                                    -hy,
                                    -hz,
                                    hy * p[2] - hz * p[1],
                                    hz * p[0] - hx * p[2],
                                    hx * p[1] - hy * p[0]};
                const float hw = huber_weight(r, huber);
                rows.push(j, r, hw);
                eq.residual_sq += static_cast<double>(r) * r;
                eq.weighted_sq += static_cast<double>(hw) * r * r;
                ++eq.used;
            }
            rows.flush(eq);
        }
    });
}

}  // namespace df::slam::tracker_detail
