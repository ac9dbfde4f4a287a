// The sensor model on scenes whose truth is simple: a flat wall, a box in front of it, a long
// floor seen at grazing angles.
#include "sim/sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/camera_path.hpp"
#include "sim/render.hpp"
#include "sim/sequence.hpp"
#include "sim_test_util.hpp"

namespace df::sim {
namespace {

constexpr int kW = 320, kH = 240;

/// A room whose far wall (y = wall_m) faces a camera at (0, 0, height) looking along +y.
Scene wall_room(double wall_m, double length_behind = 1.0) {
    Scene s;
    s.seed = 3;
    const int m = s.add_material(
        make_material("wall", Pattern::kNoise, Rgb(0.7, 0.7, 0.7), Rgb(0.5, 0.5, 0.5), 0.3));
    s.room.lo = Vec3(-6, -length_behind, 0);
    s.room.hi = Vec3(6, wall_m, 3);
    s.room.materials = {m, m, m, m, m, m};
    s.lights = {{Vec3(0, 1, 2.5), 0.5, 3.0}};
    return s;
}

RenderConfig config() {
    RenderConfig c;
    c.width = kW;
    c.height = kH;
    c.intrinsics = scale_intrinsics(io::Intrinsics{535.4, 539.2, 320.1, 247.6}, kW, kH);
    return c;
}

FrameState looking_along_y(double height) {
    FrameState state;
    state.world_T_camera = look_at(Vec3(0, 0, height), Vec3(0, 10, height));
    return state;
}

/// Standard deviation of measured minus true depth over the image centre, several frames.
double measured_sigma(double wall_m, int* valid) {
    const Scene scene = wall_room(wall_m);
    const RenderBuffers b = render(scene, looking_along_y(1.5), config());
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int frame = 0; frame < 6; ++frame) {
        const SensorFrame f =
            apply_sensor(b, SensorConfig{}, config().intrinsics, 5000, 11, frame, frame / 30.0, 2);
        for (int y = kH / 4; y < 3 * kH / 4; ++y)
            for (int x = kW / 4; x < 3 * kW / 4; ++x) {
                const uint16_t d = f.depth.at<uint16_t>(y, x);
                if (d == 0) continue;
                const double e = d / 5000.0 - b.depth_m.at<float>(y, x);
                sum += e;
                sum2 += e * e;
                ++n;
            }
    }
    *valid = n;
    const double mean = sum / n;
    return std::sqrt(sum2 / n - mean * mean);
}

TEST(SimSensor, DepthNoiseGrowsWithDepthAsModelled) {
    const SensorConfig c;
    const double fx = native_fx(c, config().intrinsics.fx, kW);
    double sigma_at[2];
    const double depths[2] = {1.0, 3.0};
    for (int i = 0; i < 2; ++i) {
        int valid = 0;
        const double z = depths[i];
        sigma_at[i] = measured_sigma(z, &valid);
        // Axial noise and the quantisation step (uniform, variance q^2 / 12) add up.
        const double q = quantisation_step(c, fx, z);
        const double expected = std::sqrt(std::pow(depth_sigma(c, z), 2) + q * q / 12);
        std::printf(
            "wall at %.1f m: measured sigma %.2f mm, model %.2f mm (noise %.2f mm, step %.2f mm), "
            "%d px\n",
            z, 1e3 * sigma_at[i], 1e3 * expected, 1e3 * depth_sigma(c, z), 1e3 * q, valid);
        EXPECT_GT(valid, 20000);
        EXPECT_NEAR(sigma_at[i] / expected, 1.0, 0.25) << "at " << z << " m";
    }
    EXPECT_GT(sigma_at[1], 4 * sigma_at[0]);
}

TEST(SimSensor, HolesAtDepthEdgesAndInTheProjectorShadowOnly) {
    Scene scene = wall_room(3.0);
    scene.statics.push_back(make_box(Vec3(-0.2, 1.4, 1.2), Vec3(0.2, 1.6, 1.8), 0));
    const RenderConfig rc = config();
    const RenderBuffers b = render(scene, looking_along_y(1.5), rc);
    const SensorFrame f = apply_sensor(b, SensorConfig{}, rc.intrinsics, 5000, 5, 0, 0.0, 2);
    // The box's columns on the centre row, from the ideal depth.
    const int row = kH / 2;
    int left = -1, right = -1;
    for (int x = 0; x < kW; ++x) {
        if (b.depth_m.at<float>(row, x) < 2.0f) {
            if (left < 0) left = x;
            right = x;
        }
    }
    ASSERT_GT(left, 0);
    ASSERT_GT(right, left + 20);
    // Shadow width: the disparity difference between box and wall, fx b (1/z1 - 1/z2).
    const double shadow_px = rc.intrinsics.fx * 0.075 * (1 / 1.5 - 1 / 3.0);
    int shadow_holes = 0, shadow_n = 0, right_holes = 0, right_n = 0, flat_holes = 0, flat_n = 0;
    int edge_holes = 0, edge_n = 0;
    for (int y = row - 20; y <= row + 20; ++y) {
        for (int x = 0; x < kW; ++x) {
            const bool hole = f.depth.at<uint16_t>(y, x) == 0;
            if (x >= left - static_cast<int>(shadow_px) + 1 && x <= left - 3) {
                shadow_n++, shadow_holes += hole;
            } else if (x >= right + 3 && x <= right + 8) {
                right_n++, right_holes += hole;
            } else if (x == left || x == right || x == left - 1 || x == right + 1) {
                edge_n++, edge_holes += hole;
            } else if (x > right + 15 || x < left - shadow_px - 15) {
                flat_n++, flat_holes += hole;
            }
        }
    }
    std::printf(
        "holes: projector shadow %d/%d, right of the box %d/%d, at edges %d/%d, flat wall %d/%d\n",
        shadow_holes, shadow_n, right_holes, right_n, edge_holes, edge_n, flat_holes, flat_n);
    EXPECT_GT(shadow_holes, 0.95 * shadow_n);
    EXPECT_LT(right_holes, 0.3 * right_n);
    EXPECT_GT(edge_holes, 0.3 * edge_n);
    EXPECT_LT(flat_holes, 0.02 * flat_n);
}

TEST(SimSensor, HolesAtGrazingAngles) {
    const Scene scene = wall_room(30.0);  // a long floor
    const RenderConfig rc = config();
    const RenderBuffers b = render(scene, looking_along_y(0.3), rc);
    SensorConfig c;
    c.max_range_m = 30;  // only the angle matters here
    const SensorFrame f = apply_sensor(b, c, rc.intrinsics, 5000, 5, 0, 0.0, 2);
    int grazing = 0, grazing_holes = 0, steep = 0, steep_holes = 0;
    const double cos_87 = std::cos(87 * M_PI / 180), cos_70 = std::cos(70 * M_PI / 180);
    for (int y = kH / 2 + 2; y < kH; ++y) {  // floor rows
        for (int x = 10; x < kW - 10; ++x) {
            if (b.depth_m.at<float>(y, x) > 10.0f) continue;  // the far wall, not the floor
            const float inc = b.incidence.at<float>(y, x);
            const bool hole = f.depth.at<uint16_t>(y, x) == 0;
            if (inc < cos_87) grazing++, grazing_holes += hole;
            if (inc > cos_70) steep++, steep_holes += hole;
        }
    }
    std::printf("floor holes: incidence > 87 deg %d/%d, < 70 deg %d/%d\n", grazing_holes, grazing,
                steep_holes, steep);
    ASSERT_GT(grazing, 200);
    ASSERT_GT(steep, 200);
    EXPECT_GT(grazing_holes, 0.8 * grazing);
    EXPECT_LT(steep_holes, 0.03 * steep);
}

TEST(SimSensor, RangeLimitsAreRespected) {
    Scene scene = wall_room(9.0);
    scene.statics.push_back(
        make_box(Vec3(-0.1, 0.25, 1.4), Vec3(0.1, 0.35, 1.6), 0));  // 0.25 m away
    const RenderConfig rc = config();
    const RenderBuffers b = render(scene, looking_along_y(1.5), rc);
    const SensorConfig c;
    const SensorFrame f = apply_sensor(b, c, rc.intrinsics, 5000, 5, 0, 0.0, 2);
    int beyond = 0, near = 0, valid = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint16_t d = f.depth.at<uint16_t>(y, x);
            const float z = b.depth_m.at<float>(y, x);
            if (d != 0) {
                ++valid;
                EXPECT_GE(d / 5000.0, c.min_range_m);
                EXPECT_LE(d / 5000.0, c.max_range_m);
            }
            if (z > 9.0f) beyond += d != 0;
            if (z < 0.35f) near += d != 0;
        }
    EXPECT_EQ(beyond, 0) << "the far wall is beyond range";
    EXPECT_EQ(near, 0) << "the box is nearer than the minimum range";
    EXPECT_GT(valid, 1000) << "side walls within range are measured";
}

TEST(SimSensor, IdealSensorGivesExactDepthAndColour) {
    Scene scene = wall_room(3.0);
    scene.statics.push_back(make_box(Vec3(-0.2, 1.4, 1.2), Vec3(0.2, 1.6, 1.8), 0));
    const RenderConfig rc = config();
    const RenderBuffers b = render(scene, looking_along_y(1.5), rc);
    const SensorConfig c = SensorConfig::ideal();
    const SensorFrame f = apply_sensor(b, c, rc.intrinsics, 5000, 5, 3, 0.1, 2);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double z = b.depth_m.at<float>(y, x);
            const uint16_t expected = z >= c.min_range_m && z <= c.max_range_m
                                          ? static_cast<uint16_t>(std::lround(z * 5000))
                                          : 0;
            ASSERT_EQ(f.depth.at<uint16_t>(y, x), expected) << x << "," << y;
            for (int ch = 0; ch < 3; ++ch) {
                const double v = 255.0 * b.colour.at<cv::Vec3f>(y, x)[ch];
                ASSERT_NEAR(f.rgb.at<cv::Vec3b>(y, x)[ch], std::clamp(v, 0.0, 255.0), 0.51);
            }
        }
}

TEST(SimSensor, ExposureDriftsOnlyWhenEnabled) {
    SensorConfig c;
    double lo = 1e9, hi = 0;
    for (int i = 0; i < 300; ++i) {
        const double g = exposure_gain(c, 4, i / 30.0);
        lo = std::min(lo, g), hi = std::max(hi, g);
    }
    EXPECT_GT(hi - lo, 0.05);
    EXPECT_LT(hi - lo, 2 * c.exposure_amplitude + 1e-9);
    c.exposure_changes = false;
    EXPECT_EQ(exposure_gain(c, 4, 1.0), c.gain);
}

}  // namespace
}  // namespace df::sim
