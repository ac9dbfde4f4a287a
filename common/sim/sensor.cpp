#include "sim/sensor.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "sim/motion.hpp"
#include "sim/parallel.hpp"
#include "sim/rng.hpp"

namespace df::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

enum Channel : uint64_t {
    kEdge = 1,
    kEdgeFar,
    kGrazing,
    kDropout,
    kSpeckle,
    kDepthNoise,
    kRed,
    kGreen,
    kBlue,
};

/// Marks pixels whose projector ray is blocked by a nearer surface. The projector sits at +x
/// (baseline b): a surface point at column u with disparity D = fx b / z is lit through projector
/// column u - D; a pixel is in shadow when a pixel at least margin px nearer covers the same
/// projector column (a 1-D z-buffer per row, in projector columns).
void shadow_row(const float* depth, int width, float fx_b, float margin, std::vector<float>* disp,
                std::vector<float>* buf, uint8_t* shadow) {
    disp->assign(static_cast<size_t>(width), 0.0f);
    float max_disp = 0;
    for (int x = 0; x < width; ++x) {
        if (depth[x] > 0) (*disp)[x] = fx_b / depth[x];
        max_disp = std::max(max_disp, (*disp)[x]);
    }
    // Projector columns x - D are shifted by `offset` so that bins are non-negative.
    const int offset = static_cast<int>(std::ceil(max_disp)) + 2;
    const int bins = width + offset + 2;
    buf->assign(static_cast<size_t>(bins), 0.0f);
    for (int x = 0; x < width; ++x) {
        const float d = (*disp)[x];
        if (d <= 0) continue;
        const float column = x - d + offset;  // >= 1.5
        const int b0 = static_cast<int>(column - 0.5f),
                  b1 = std::min(bins - 1, static_cast<int>(column + 0.5f));
        for (int b = b0; b <= b1; ++b) (*buf)[b] = std::max((*buf)[b], d);
    }
    for (int x = 0; x < width; ++x) {
        const float d = (*disp)[x];
        shadow[x] = d > 0 && (*buf)[static_cast<int>(x - d + offset)] > d + margin;
    }
}

/// True if pixel (x, y) differs from a neighbour at distance `step` by more than `jump` relative
/// (to the nearer of the two), or a neighbour has no depth.
bool at_edge(const cv::Mat& depth, int x, int y, int step, float jump) {
    const float* row = depth.ptr<float>(y);
    const float z = row[x];
    auto differs = [&](float zn) { return zn <= 0 || std::abs(zn - z) > jump * std::min(z, zn); };
    if (x >= step && differs(row[x - step])) return true;
    if (x + step < depth.cols && differs(row[x + step])) return true;
    if (y >= step && differs(depth.ptr<float>(y - step)[x])) return true;
    if (y + step < depth.rows && differs(depth.ptr<float>(y + step)[x])) return true;
    return false;
}

/// Per-pixel random numbers: one mix for the pixel, one more per use.
struct PixelRandom {
    uint64_t base;
    PixelRandom(uint64_t frame_seed, uint64_t pixel)
        : base(mix64(frame_seed ^ (pixel * 0x9E3779B97F4A7C15ull))) {}
    uint64_t bits(uint64_t channel) const { return mix64(base + channel * 0xD1B54A32D192ED03ull); }
    double uniform(uint64_t channel) const { return unit_from_bits(bits(channel)); }
    double normal(uint64_t channel) const { return normal_from_bits(bits(channel)); }
};

}  // namespace

SensorConfig SensorConfig::ideal() {
    SensorConfig c;
    c.depth_noise = c.quantisation = c.projector_shadow = c.edge_holes = c.grazing_holes = false;
    c.dropouts = c.colour_noise = c.exposure_changes = c.vignetting = c.colour_blur = false;
    c.motion_blur = false;
    return c;
}

const std::vector<std::string>& sensor_effects() {
    static const std::vector<std::string> names = {
        "depth_noise", "quantisation", "projector_shadow", "edge_holes", "grazing_holes",
        "dropouts",    "colour_noise", "exposure_changes", "vignetting", "colour_blur",
        "motion_blur"};
    return names;
}

bool set_sensor_effect(SensorConfig* c, const std::string& name, bool enabled) {
    bool* flags[] = {
        &c->depth_noise, &c->quantisation, &c->projector_shadow, &c->edge_holes, &c->grazing_holes,
        &c->dropouts,    &c->colour_noise, &c->exposure_changes, &c->vignetting, &c->colour_blur,
        &c->motion_blur};
    const auto& names = sensor_effects();
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i] == name) {
            *flags[i] = enabled;
            return true;
        }
    }
    return false;
}

double depth_sigma(const SensorConfig& c, double z) {
    if (!c.depth_noise) return 0;
    const double dz = z - c.sigma_z0_m;
    return c.sigma_a_m + c.sigma_b_per_m * dz * dz;
}

double native_fx(const SensorConfig& c, double fx, int width) {
    return fx * c.native_width_px / width;
}

double quantisation_step(const SensorConfig& c, double fx_native, double z) {
    if (!c.quantisation) return 0;
    return z * z * c.disparity_step_px / (fx_native * c.baseline_m);
}

double exposure_gain(const SensorConfig& c, uint64_t seed, double t_s) {
    if (!c.exposure_changes) return c.gain;
    return c.gain * (1.0 + c.exposure_amplitude * wobble(seed, 301, t_s, 0.03, 0.25) / 1.5);
}

SensorFrame apply_sensor(const RenderBuffers& r, const SensorConfig& c, const io::Intrinsics& k,
                         double units_per_m, uint64_t seed, int frame, double t_s, int threads) {
    const int w = r.depth_m.cols, h = r.depth_m.rows;
    const uint64_t frame_seed = hash64(seed, static_cast<uint64_t>(frame), 0x5E);
    const double fx_b = k.fx * c.baseline_m;  // projector geometry, in this image's pixels
    const double fx_b_native = native_fx(c, k.fx, w) * c.baseline_m;  // disparity steps
    const double cos_start = std::cos(c.grazing_start_deg * kPi / 180);
    const double cos_full = std::cos(c.grazing_full_deg * kPi / 180);
    const float jump = static_cast<float>(c.edge_jump);
    SensorFrame out;
    out.depth.create(h, w, CV_16UC1);
    parallel_rows(h, threads, [&](int y0, int y1) {
        std::vector<float> disp, buf;
        std::vector<uint8_t> shadow(static_cast<size_t>(w), 0);
        for (int y = y0; y < y1; ++y) {
            const float* z_row = r.depth_m.ptr<float>(y);
            const float* inc = r.incidence.ptr<float>(y);
            const float* drop = r.dropout.ptr<float>(y);
            uint16_t* dst = out.depth.ptr<uint16_t>(y);
            if (c.projector_shadow) {
                shadow_row(z_row, w, static_cast<float>(fx_b),
                           static_cast<float>(c.shadow_margin_px), &disp, &buf, shadow.data());
            }
            for (int x = 0; x < w; ++x) {
                dst[x] = 0;
                double z = z_row[x];
                if (!(z > 0)) continue;
                const PixelRandom random(frame_seed, static_cast<uint64_t>(y) * w + x);
                if (c.projector_shadow && shadow[x]) continue;
                if (c.edge_holes) {
                    if (at_edge(r.depth_m, x, y, 1, jump) &&
                        random.uniform(kEdge) < c.edge_hole_probability)
                        continue;
                    if (at_edge(r.depth_m, x, y, 2, jump) &&
                        random.uniform(kEdgeFar) < c.edge_hole_probability / 3)
                        continue;
                }
                if (c.grazing_holes && inc[x] < cos_start) {
                    const double p = (cos_start - inc[x]) / (cos_start - cos_full);
                    if (random.uniform(kGrazing) < p) continue;
                }
                if (c.dropouts) {
                    if (drop[x] > 0 && random.uniform(kDropout) < drop[x]) continue;
                    if (random.uniform(kSpeckle) < c.speckle_probability) continue;
                }
                if (c.depth_noise) z += depth_sigma(c, z) * random.normal(kDepthNoise);
                if (c.quantisation && z > 0) {
                    const double disparity = fx_b_native / z;
                    const double q =
                        std::round(disparity / c.disparity_step_px) * c.disparity_step_px;
                    if (q <= 0) continue;
                    z = fx_b_native / q;
                }
                if (z < c.min_range_m || z > c.max_range_m) continue;
                const double units = std::round(z * units_per_m);
                if (units >= 1 && units <= 65535) dst[x] = static_cast<uint16_t>(units);
            }
        }
    });

    // Colour: exposure and vignetting, blur, then noise and 8 bits.
    const double gain = exposure_gain(c, seed, t_s) * 255.0;
    cv::Mat linear(h, w, CV_32FC3);
    const double cx = k.cx, cy = k.cy;
    const double r2_max =
        std::max(cx * cx, (w - cx) * (w - cx)) + std::max(cy * cy, (h - cy) * (h - cy));
    parallel_rows(h, threads, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const auto* src = r.colour.ptr<cv::Vec3f>(y);
            auto* dst = linear.ptr<cv::Vec3f>(y);
            for (int x = 0; x < w; ++x) {
                double g = gain;
                if (c.vignetting) {
                    const double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2_max;
                    g *= 1.0 - c.vignetting_strength * r2;
                }
                dst[x] = src[x] * static_cast<float>(g);
            }
        }
    });
    if (c.colour_blur && c.blur_sigma_px > 0) {
        cv::GaussianBlur(linear, linear, cv::Size(0, 0), c.blur_sigma_px, c.blur_sigma_px,
                         cv::BORDER_REPLICATE);
    }
    out.rgb.create(h, w, CV_8UC3);
    // Noise sigma per 8-bit level: read noise plus shot noise.
    float sigma_of_level[258];
    for (int v = 0; v < 258; ++v)
        sigma_of_level[v] =
            static_cast<float>(std::sqrt(c.colour_sigma * c.colour_sigma + 0.02 * v));
    parallel_rows(h, threads, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const auto* src = linear.ptr<cv::Vec3f>(y);
            auto* dst = out.rgb.ptr<cv::Vec3b>(y);
            for (int x = 0; x < w; ++x) {
                const PixelRandom random(frame_seed, static_cast<uint64_t>(y) * w + x);
                for (int ch = 0; ch < 3; ++ch) {
                    double v = src[x][ch];
                    if (c.colour_noise) {
                        const int level = static_cast<int>(std::clamp(v, 0.0, 257.0));
                        v += sigma_of_level[level] * random.normal(kRed + ch);
                    }
                    dst[x][ch] = cv::saturate_cast<uint8_t>(v);  // rounds to nearest
                }
            }
        }
    });
    return out;
}

}  // namespace df::sim
