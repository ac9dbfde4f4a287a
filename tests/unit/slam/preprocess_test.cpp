#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

#include "slam/depth_maps.hpp"
#include "slam/frame.hpp"

namespace df::slam {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr double kUnitsPerM = 5000.0;

io::Intrinsics tum_intrinsics() { return io::Intrinsics{}; }

/// An image whose depth (metres) at pixel (u, v) is `depth_at(u, v)`, rgb mid-grey.
io::RgbdImage make_image(const std::function<double(int, int)>& depth_at) {
    io::RgbdImage image;
    image.depth = cv::Mat(kHeight, kWidth, CV_16UC1);
    image.rgb = cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(128, 128, 128));
    image.depth_units_per_m = kUnitsPerM;
    for (int v = 0; v < kHeight; ++v) {
        for (int u = 0; u < kWidth; ++u) {
            const double z = depth_at(u, v);
            image.depth.at<uint16_t>(v, u) =
                z > 0 ? static_cast<uint16_t>(std::lround(z * kUnitsPerM)) : uint16_t{0};
        }
    }
    return image;
}

/// Depth of the plane n . X = d seen along the ray of pixel (u, v).
double plane_depth(const io::Intrinsics& k, const cv::Vec3d& n, double d, int u, int v) {
    const cv::Vec3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
    return d / n.dot(ray);
}

Frame preprocess_ok(const io::RgbdImage& image, const PreprocessConfig& config = {}) {
    Result<Frame> frame = preprocess(image, config);
    EXPECT_TRUE(frame.is_ok()) << frame.status().to_string();
    return std::move(frame).value();
}

TEST(Preprocess, LevelSizesAndTypes) {
    const Frame frame = preprocess_ok(make_image([](int, int) { return 1.5; }));
    ASSERT_EQ(frame.levels.size(), 3u);
    const int widths[] = {640, 320, 160}, heights[] = {480, 240, 120};
    for (size_t l = 0; l < 3; ++l) {
        const FrameLevel& level = frame.levels[l];
        for (const cv::Mat* m : {&level.depth_m, &level.smoothed_depth_m, &level.intensity,
                                 &level.grad_x, &level.grad_y, &level.vertex, &level.normal}) {
            EXPECT_EQ(m->cols, widths[l]) << "level " << l;
            EXPECT_EQ(m->rows, heights[l]) << "level " << l;
        }
        EXPECT_EQ(level.depth_m.type(), CV_32F);
        EXPECT_EQ(level.smoothed_depth_m.type(), CV_32F);
        EXPECT_EQ(level.intensity.type(), CV_32F);
        EXPECT_EQ(level.grad_x.type(), CV_32F);
        EXPECT_EQ(level.vertex.type(), CV_32FC3);
        EXPECT_EQ(level.normal.type(), CV_32FC3);
    }
}

TEST(Preprocess, FrontoParallelPlane) {
    const Frame frame = preprocess_ok(make_image([](int, int) { return 1.5; }));
    for (size_t l = 0; l < frame.levels.size(); ++l) {
        const FrameLevel& level = frame.levels[l];
        int valid_normals = 0;
        for (int v = 0; v < level.height(); ++v) {
            for (int u = 0; u < level.width(); ++u) {
                const cv::Vec3f p = level.vertex.at<cv::Vec3f>(v, u);
                ASSERT_NEAR(p[2], 1.5f, 1e-5f);
                const io::Intrinsics& k = level.intrinsics;
                ASSERT_NEAR(p[0], (u - k.cx) / k.fx * 1.5, 1e-5);
                ASSERT_NEAR(p[1], (v - k.cy) / k.fy * 1.5, 1e-5);
                const cv::Vec3f n = level.normal.at<cv::Vec3f>(v, u);
                const int b = PreprocessConfig{}.normal_baseline_px;
                const bool border =
                    u < b || v < b || u >= level.width() - b || v >= level.height() - b;
                ASSERT_EQ(is_valid_normal(n), !border) << "level " << l << " at " << u << "," << v;
                if (border) continue;
                ++valid_normals;
                EXPECT_NEAR(n[0], 0.f, 2e-4f);  // float rounding of the filter
                EXPECT_NEAR(n[1], 0.f, 2e-4f);
                EXPECT_NEAR(n[2], -1.f, 1e-7f);
                EXPECT_LT(n.dot(p), 0.f);
            }
        }
        const int b = PreprocessConfig{}.normal_baseline_px;
        EXPECT_EQ(valid_normals, (level.width() - 2 * b) * (level.height() - 2 * b));
    }
}

TEST(Preprocess, TiltedPlaneNormalWithinOneDegree) {
    const io::Intrinsics k = tum_intrinsics();
    // Plane facing the camera, tilted about 26 deg about y and 19 deg about x, 1.5 m on the axis
    // (so all of it lies within the 3 m range: no validity border inside the image).
    cv::Vec3d n(std::sin(0.52), std::sin(0.35), -1.0);
    n /= cv::norm(n);
    const double d = n.dot(cv::Vec3d(0, 0, 1.5));
    const Frame frame =
        preprocess_ok(make_image([&](int u, int v) { return plane_depth(k, n, d, u, v); }));
    for (size_t l = 0; l < frame.levels.size(); ++l) {
        const FrameLevel& level = frame.levels[l];
        const int margin = 4;
        int checked = 0;
        for (int v = margin; v < level.height() - margin; ++v) {
            for (int u = margin; u < level.width() - margin; ++u) {
                const cv::Vec3f nf = level.normal.at<cv::Vec3f>(v, u);
                ASSERT_TRUE(is_valid_normal(nf));
                const double cos_angle = cv::Vec3d(nf[0], nf[1], nf[2]).dot(n);
                ASSERT_GT(cos_angle, std::cos(1.0 * CV_PI / 180.0))
                    << "level " << l << " at " << u << "," << v;
                ASSERT_NEAR(cv::norm(nf), 1.0, 1e-5);
                // Vertices lie on the plane (to the 0.2 mm depth quantisation).
                const cv::Vec3f p = level.vertex.at<cv::Vec3f>(v, u);
                ASSERT_NEAR(cv::Vec3d(p[0], p[1], p[2]).dot(n) - d, 0.0, 1e-3);
                ++checked;
            }
        }
        EXPECT_GT(checked, 0);
    }
}

TEST(Preprocess, OutOfRangeDepthIsInvalid) {
    // Columns: 0.2 m (too near), 1 m, 6.5 m (too far), 0 (no reading).
    const Frame frame = preprocess_ok(make_image([](int u, int) {
        return u < 160 ? 0.2 : u < 320 ? 1.0 : u < 480 ? 6.5 : 0.0;
    }));
    const FrameLevel& base = frame.levels[0];
    for (int u : {10, 100, 200, 300, 400, 470, 500, 630}) {
        const bool valid = u >= 160 && u < 320;
        const float z = base.depth_m.at<float>(240, u);
        EXPECT_EQ(z > 0.f, valid) << u;
        EXPECT_EQ(base.smoothed_depth_m.at<float>(240, u) > 0.f, valid) << u;
        EXPECT_EQ(is_valid_vertex(base.vertex.at<cv::Vec3f>(240, u)), valid) << u;
        EXPECT_EQ(is_valid_normal(base.normal.at<cv::Vec3f>(240, u)), valid) << u;
        EXPECT_FALSE(std::isnan(z));
    }
    // Normals need all 4 neighbours, normal_baseline_px away: the columns that close to the
    // invalid ones have none.
    const int b = PreprocessConfig{}.normal_baseline_px;
    EXPECT_FALSE(is_valid_normal(base.normal.at<cv::Vec3f>(240, 320 - b)));
    EXPECT_FALSE(is_valid_normal(base.normal.at<cv::Vec3f>(240, 160 + b - 1)));
    EXPECT_TRUE(is_valid_normal(base.normal.at<cv::Vec3f>(240, 160 + b)));
    EXPECT_TRUE(is_valid_normal(base.normal.at<cv::Vec3f>(240, 319 - b)));

    PreprocessConfig far;
    far.max_depth_m = 4.0f;
    EXPECT_NEAR(preprocess_ok(make_image([](int, int) { return 3.5; }), far)
                    .levels[0]
                    .depth_m.at<float>(240, 320),
                3.5f, 1e-4f);
}

TEST(Preprocess, StepEdgeIsNotSmoothedAcross) {
    // Near plane at 1.0 m left of column 321, far plane at 1.5 m right of it: 0.5 m apart is
    // over 16 sigma of the range kernel.
    const Frame frame = preprocess_ok(make_image([](int u, int) { return u < 321 ? 1.0 : 1.5; }));
    const FrameLevel& base = frame.levels[0];
    for (int u = 300; u < 340; ++u) {
        EXPECT_NEAR(base.smoothed_depth_m.at<float>(240, u), u < 321 ? 1.0f : 1.5f, 1e-5f) << u;
    }
    // Block 160 at level 1 holds columns 320 (near) and 321 (far); it must be one or the other.
    for (size_t l = 1; l < frame.levels.size(); ++l) {
        const FrameLevel& level = frame.levels[l];
        const int row = level.height() / 2;
        for (int u = 0; u < level.width(); ++u) {
            for (const cv::Mat* depth : {&level.depth_m, &level.smoothed_depth_m}) {
                const float z = depth->at<float>(row, u);
                EXPECT_TRUE(std::fabs(z - 1.0f) < 1e-5f || std::fabs(z - 1.5f) < 1e-5f)
                    << "level " << l << " column " << u << " depth " << z;
            }
        }
    }
}

TEST(Preprocess, BilateralSmoothsNoiseOnAPlane) {
    // +-1 mm checkerboard noise on a plane at 1 m is averaged out (a 5x5 window).
    cv::Mat depth(64, 64, CV_32F);
    for (int v = 0; v < depth.rows; ++v) {
        for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = (u + v) % 2 ? 1.001f : 0.999f;
    }
    const cv::Mat smoothed = bilateral_filter_depth(depth, 4.5f, 0.03f, 2);
    for (int v = 2; v < 62; ++v) {
        for (int u = 2; u < 62; ++u) EXPECT_NEAR(smoothed.at<float>(v, u), 1.0f, 1.5e-4f);
    }
}

/// The bilateral filter as its contract in depth_maps.hpp reads, one pixel at a time in double
/// with std::exp. Only the 4 sigma cut-off is decided in float (dz and dz^2 rounded as the filter
/// rounds them), so that a neighbour exactly at the cut-off counts or not the same way in both.
cv::Mat reference_bilateral(const cv::Mat& depth, float sigma_space_px, float sigma_depth_m,
                            int radius) {
    cv::Mat out(depth.size(), CV_32F, cv::Scalar(0));
    const float cutoff_dz2 = 16.f * sigma_depth_m * sigma_depth_m;
    for (int v = 0; v < depth.rows; ++v) {
        for (int u = 0; u < depth.cols; ++u) {
            const float center = depth.at<float>(v, u);
            if (!(center > 0.f)) continue;
            double sum = 0, weight_sum = 0;
            for (int dv = -radius; dv <= radius; ++dv) {
                for (int du = -radius; du <= radius; ++du) {
                    if (v + dv < 0 || v + dv >= depth.rows || u + du < 0 || u + du >= depth.cols)
                        continue;
                    const float z = depth.at<float>(v + dv, u + du);
                    const float dz = z - center;
                    if (!(z > 0.f) || dz * dz > cutoff_dz2) continue;
                    const double w =
                        std::exp(-(du * du + dv * dv) / (2.0 * sigma_space_px * sigma_space_px)) *
                        std::exp(-double{dz} * dz / (2.0 * sigma_depth_m * sigma_depth_m));
                    sum += w * z;
                    weight_sum += w;
                }
            }
            out.at<float>(v, u) = static_cast<float>(sum / weight_sum);
        }
    }
    return out;
}

/// Noisy depth with holes and steps: a tilted plane, a box 0.3 m in front, strips 5 cm and 11 cm
/// (near the 4 sigma cut-off) proud of the plane, 3 mm Gaussian noise, scattered invalid pixels
/// and invalid blocks. Width not a multiple of 4 or 8.
cv::Mat noisy_depth_with_holes_and_steps(int width, int height) {
    cv::Mat depth(height, width, CV_32F);
    cv::RNG rng(7);
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            double z = 1.2 + 0.006 * u + 0.003 * v;
            if (u > width / 3 && u < width / 2 && v > height / 4 && v < height / 2) z -= 0.3;
            if (u % 29 < 6) z -= 0.05;
            if (v % 23 < 4) z -= 0.11;
            z += rng.gaussian(0.003);
            if (rng.uniform(0.0, 1.0) < 0.1 || ((u / 16 + v / 16) % 9 == 0 && u % 16 < 5)) z = 0;
            depth.at<float>(v, u) = static_cast<float>(z);
        }
    }
    return depth;
}

TEST(Preprocess, BilateralMatchesReferenceImplementation) {
    const cv::Mat depth = noisy_depth_with_holes_and_steps(203, 117);
    struct Params {
        float sigma_space_px, sigma_depth_m;
        int radius;
    };
    for (const Params& p : {Params{4.5f, 0.03f, 2}, Params{1.0f, 0.01f, 1}, Params{2.0f, 0.05f, 4},
                            Params{3.0f, 0.02f, 0}}) {
        const cv::Mat fast =
            bilateral_filter_depth(depth, p.sigma_space_px, p.sigma_depth_m, p.radius);
        const cv::Mat reference =
            reference_bilateral(depth, p.sigma_space_px, p.sigma_depth_m, p.radius);
        ASSERT_EQ(fast.size(), depth.size());
        ASSERT_EQ(fast.type(), CV_32F);
        double max_diff = 0;
        for (int v = 0; v < depth.rows; ++v) {
            for (int u = 0; u < depth.cols; ++u) {
                const float z = fast.at<float>(v, u);
                ASSERT_EQ(z > 0.f, depth.at<float>(v, u) > 0.f) << u << "," << v;
                max_diff = std::max(max_diff, std::fabs(double{z} - reference.at<float>(v, u)));
            }
        }
        EXPECT_LE(max_diff, 1e-5) << "radius " << p.radius << " sigma_depth " << p.sigma_depth_m;
        if (p.radius == 0) {
            EXPECT_EQ(cv::norm(fast, depth, cv::NORM_INF), 0.0);  // only the pixel itself
        }
        std::printf("radius %d: max |fast - reference| = %.3g m\n", p.radius, max_diff);
    }
}

TEST(Preprocess, BilateralOfQuantisedSensorDepthMatchesReference) {
    // Sensor depth comes in 0.2 mm steps, so depth differences of exactly 4 sigma (600 steps)
    // are common at edges: the cut-off must decide them as the reference does.
    io::RgbdImage image = make_image([](int u, int v) {
        return 1.0 + 0.12 * ((u / 7 + v / 5) % 3) + 0.0002 * ((u * 31 + v * 17) % 11);
    });
    const cv::Mat depth = depth_to_metres(image.depth, kUnitsPerM, 0.3f, 3.f);
    const cv::Mat fast = bilateral_filter_depth(depth, 4.5f, 0.03f, 2);
    const cv::Mat reference = reference_bilateral(depth, 4.5f, 0.03f, 2);
    const double max_diff = cv::norm(fast, reference, cv::NORM_INF);
    EXPECT_LE(max_diff, 1e-5);
    std::printf("quantised: max |fast - reference| = %.3g m\n", max_diff);
}

// One-pixel-at-a-time versions of the other building blocks, as their contracts in
// depth_maps.hpp read; the library's row-parallel SIMD versions must match them bit for bit.

cv::Mat reference_vertex_map(const cv::Mat& depth, const io::Intrinsics& k) {
    cv::Mat out(depth.size(), CV_32FC3);
    for (int v = 0; v < depth.rows; ++v) {
        const float ray_y = static_cast<float>((v - k.cy) / k.fy);
        for (int u = 0; u < depth.cols; ++u) {
            const float ray_x = static_cast<float>((u - k.cx) / k.fx);
            const float z = depth.at<float>(v, u);
            out.at<cv::Vec3f>(v, u) =
                z > 0.f ? cv::Vec3f(ray_x * z, ray_y * z, z) : cv::Vec3f(0.f, 0.f, 0.f);
        }
    }
    return out;
}

cv::Mat reference_normal_map(const cv::Mat& vertex, int b = 1) {
    cv::Mat out(vertex.size(), CV_32FC3, cv::Scalar::all(0));
    for (int v = b; v + b < vertex.rows; ++v) {
        for (int u = b; u + b < vertex.cols; ++u) {
            const cv::Vec3f mid = vertex.at<cv::Vec3f>(v, u);
            const cv::Vec3f left = vertex.at<cv::Vec3f>(v, u - b);
            const cv::Vec3f right = vertex.at<cv::Vec3f>(v, u + b);
            const cv::Vec3f up = vertex.at<cv::Vec3f>(v - b, u);
            const cv::Vec3f down = vertex.at<cv::Vec3f>(v + b, u);
            if (mid[2] <= 0.f || left[2] <= 0.f || right[2] <= 0.f || up[2] <= 0.f ||
                down[2] <= 0.f) {
                continue;
            }
            cv::Vec3f n = (down - up).cross(right - left);
            const float norm = std::sqrt(n.dot(n));
            if (!(norm > 1e-12f)) continue;
            n *= 1.f / norm;
            if (n.dot(mid) > 0.f) n = -n;
            out.at<cv::Vec3f>(v, u) = n;
        }
    }
    return out;
}

cv::Mat reference_downsample(const cv::Mat& depth, float max_diff_m) {
    cv::Mat out(depth.rows / 2, depth.cols / 2, CV_32F);
    for (int v = 0; v < out.rows; ++v) {
        for (int u = 0; u < out.cols; ++u) {
            const float block[4] = {
                depth.at<float>(2 * v, 2 * u), depth.at<float>(2 * v, 2 * u + 1),
                depth.at<float>(2 * v + 1, 2 * u), depth.at<float>(2 * v + 1, 2 * u + 1)};
            const float* ref = std::find_if(block, block + 4, [](float z) { return z > 0.f; });
            float sum = 0.f;
            int count = 0;
            for (float z : block) {
                if (ref != block + 4 && z > 0.f && std::fabs(z - *ref) <= max_diff_m) {
                    sum += z;
                    ++count;
                }
            }
            out.at<float>(v, u) = count > 0 ? sum / static_cast<float>(count) : 0.f;
        }
    }
    return out;
}

/// True when a and b have the same size, type and bytes (so -0 and +0 differ).
bool bit_identical(const cv::Mat& a, const cv::Mat& b) {
    if (a.size() != b.size() || a.type() != b.type()) return false;
    for (int v = 0; v < a.rows; ++v) {
        if (std::memcmp(a.ptr(v), b.ptr(v), a.cols * a.elemSize()) != 0) return false;
    }
    return true;
}

TEST(Preprocess, MapsAreBitIdenticalToOnePixelReferences) {
    const io::Intrinsics k = tum_intrinsics();
    // Odd and tiny sizes exercise the partial SIMD blocks at row ends.
    for (const cv::Size size : {cv::Size(203, 117), cv::Size(64, 48), cv::Size(9, 5),
                                cv::Size(5, 4), cv::Size(3, 3), cv::Size(2, 7), cv::Size(1, 1)}) {
        const cv::Mat depth = noisy_depth_with_holes_and_steps(size.width, size.height);
        const cv::Mat smoothed = bilateral_filter_depth(depth, 4.5f, 0.03f, 2);
        const cv::Mat vertex = compute_vertex_map(smoothed, k);
        const std::string where = std::to_string(size.width) + "x" + std::to_string(size.height);
        EXPECT_TRUE(bit_identical(vertex, reference_vertex_map(smoothed, k))) << where;
        const cv::Mat normal = reference_normal_map(vertex);
        EXPECT_TRUE(bit_identical(compute_normal_map(vertex), normal)) << where;
        EXPECT_TRUE(bit_identical(compute_normal_map(smoothed, k), normal)) << where;
        for (int b : {2, 3}) {
            const cv::Mat wide = reference_normal_map(vertex, b);
            EXPECT_TRUE(bit_identical(compute_normal_map(vertex, b), wide)) << where << " b=" << b;
            EXPECT_TRUE(bit_identical(compute_normal_map(smoothed, k, b), wide))
                << where << " b=" << b;
        }
        EXPECT_TRUE(
            bit_identical(downsample_depth(depth, 0.09f), reference_downsample(depth, 0.09f)))
            << where;

        cv::Mat rgb(size, CV_8UC3);
        cv::RNG(3).fill(rgb, cv::RNG::UNIFORM, 0, 256);
        cv::Mat intensity(size, CV_32F);
        for (int v = 0; v < size.height; ++v) {
            for (int u = 0; u < size.width; ++u) {
                const cv::Vec3b p = rgb.at<cv::Vec3b>(v, u);
                intensity.at<float>(v, u) = 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
            }
        }
        EXPECT_TRUE(bit_identical(rgb_to_intensity(rgb), intensity)) << where;
    }
}

TEST(Preprocess, IntensityAndGradientOfRamp) {
    io::RgbdImage image = make_image([](int, int) { return 1.5; });
    // Horizontal grey ramp I = 0.25 x (0..159.75), vertical constant.
    for (int v = 0; v < kHeight; ++v) {
        for (int u = 0; u < kWidth; ++u) {
            const uint8_t g = static_cast<uint8_t>(u / 4);
            image.rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(g, g, g);
        }
    }
    const Frame frame = preprocess_ok(image);
    const FrameLevel& base = frame.levels[0];
    EXPECT_NEAR(base.intensity.at<float>(10, 41), 10.f, 1e-4f);
    // Integer steps every 4 px: the Sobel estimate over a 3-px span averages to 0.25 over 4 px.
    double sum = 0;
    for (int u = 8; u < 8 + 4 * 100; ++u) sum += base.grad_x.at<float>(240, u);
    EXPECT_NEAR(sum / 400.0, 0.25, 1e-4);
    EXPECT_NEAR(base.grad_y.at<float>(240, 100), 0.f, 1e-6f);

    // A ramp of exact slope: 3 per pixel in x, 2 per pixel in y, in each colour.
    image.rgb.forEach<cv::Vec3b>([](cv::Vec3b& p, const int* pos) {
        const uint8_t g = static_cast<uint8_t>((3 * pos[1] + 2 * pos[0]) % 256);
        p = cv::Vec3b(g, g, g);
    });
    const Frame ramp = preprocess_ok(image);
    for (int v = 1; v < 40; ++v) {
        for (int u = 1; u < 40; ++u) {
            ASSERT_NEAR(ramp.levels[0].grad_x.at<float>(v, u), 3.f, 1e-4f) << u << "," << v;
            ASSERT_NEAR(ramp.levels[0].grad_y.at<float>(v, u), 2.f, 1e-4f) << u << "," << v;
        }
    }
    // One level down, pixels are twice as large: the slope per pixel doubles.
    for (int v = 2; v < 18; ++v) {
        for (int u = 2; u < 18; ++u) {
            ASSERT_NEAR(ramp.levels[1].grad_x.at<float>(v, u), 6.f, 1e-3f) << u << "," << v;
            ASSERT_NEAR(ramp.levels[1].grad_y.at<float>(v, u), 4.f, 1e-3f) << u << "," << v;
        }
    }
}

TEST(Preprocess, IntrinsicsScalePerLevel) {
    const io::Intrinsics k = tum_intrinsics();
    const cv::Vec3d points[] = {{0.3, -0.2, 1.7}, {-0.5, 0.4, 2.2}, {0.0, 0.0, 1.0}};
    for (int l = 0; l < 4; ++l) {
        const io::Intrinsics kl = scale_intrinsics(k, l);
        const double s = 1.0 / (1 << l);
        EXPECT_DOUBLE_EQ(kl.fx, k.fx * s);
        EXPECT_DOUBLE_EQ(kl.fy, k.fy * s);
        for (const cv::Vec3d& p : points) {
            const double u0 = k.fx * p[0] / p[2] + k.cx, v0 = k.fy * p[1] / p[2] + k.cy;
            const double ul = kl.fx * p[0] / p[2] + kl.cx, vl = kl.fy * p[1] / p[2] + kl.cy;
            // Pixel centres: level-l pixel i covers level-0 pixels [2^l i, 2^l (i+1)).
            EXPECT_NEAR(ul + 0.5, (u0 + 0.5) * s, 1e-9);
            EXPECT_NEAR(vl + 0.5, (v0 + 0.5) * s, 1e-9);
        }
    }
    const Frame frame = preprocess_ok(make_image([](int, int) { return 1.5; }));
    for (size_t l = 0; l < frame.levels.size(); ++l) {
        EXPECT_DOUBLE_EQ(frame.levels[l].intrinsics.cx,
                         scale_intrinsics(k, static_cast<int>(l)).cx);
    }
}

TEST(Preprocess, RejectsBadInput) {
    io::RgbdImage image = make_image([](int, int) { return 1.5; });
    PreprocessConfig bad;
    bad.min_depth_m = 2.f;
    bad.max_depth_m = 1.f;
    Result<Frame> r = preprocess(image, bad);
    ASSERT_FALSE(r.is_ok());
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(r.status().message().find("min_depth_m"), std::string::npos);

    io::RgbdImage wrong_rgb = image;
    wrong_rgb.rgb = cv::Mat(10, 10, CV_8UC3);
    EXPECT_FALSE(preprocess(wrong_rgb, {}).is_ok());
    io::RgbdImage float_depth = image;
    image.depth.convertTo(float_depth.depth, CV_32F);
    EXPECT_FALSE(preprocess(float_depth, {}).is_ok());
    io::RgbdImage no_units = image;
    no_units.depth_units_per_m = 0;
    EXPECT_FALSE(preprocess(no_units, {}).is_ok());
}

TEST(Preprocess, DeterministicAcrossThreadCounts) {
    const io::Intrinsics k = tum_intrinsics();
    const cv::Vec3d n = cv::normalize(cv::Vec3d(0.2, -0.1, -1.0));
    io::RgbdImage image = make_image([&](int u, int v) {
        return plane_depth(k, n, n.dot(cv::Vec3d(0, 0, 2.0)), u, v) + ((u * 7 + v * 13) % 5) * 2e-3;
    });
    const int threads = cv::getNumThreads();
    cv::setNumThreads(1);
    const Frame one = preprocess_ok(image);
    cv::setNumThreads(std::max(threads, 2));
    const Frame many = preprocess_ok(image);
    cv::setNumThreads(threads);
    for (size_t l = 0; l < one.levels.size(); ++l) {
        EXPECT_EQ(
            cv::norm(one.levels[l].smoothed_depth_m, many.levels[l].smoothed_depth_m, cv::NORM_INF),
            0.0);
        EXPECT_EQ(cv::norm(one.levels[l].normal, many.levels[l].normal, cv::NORM_INF), 0.0);
    }
}

}  // namespace
}  // namespace df::slam
