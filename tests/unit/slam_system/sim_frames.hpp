#pragma once
// Frames of a generated sequence rendered in memory (no files), as a capture would deliver
// them, with the ground-truth camera pose of each.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "io/rgbd_image.hpp"
#include "sim/sequence.hpp"

namespace df::test {

struct SimFrame {
    io::RgbdImage image;
    Eigen::Isometry3d world_T_camera;  ///< ground truth
};

/// A preset with Kinect-like sensor noise, `frames` frames long.
inline sim::Sequence make_noisy_sequence(const std::string& preset, int frames) {
    sim::PresetOptions options;
    options.frames = frames;
    options.noise = true;
    auto s = sim::make_sequence(preset, options);
    EXPECT_TRUE(s.is_ok()) << s.status().message();
    return *s;
}

/// Renders frame i of `s` with its sensor model (noise as the preset says).
inline SimFrame render_sim_frame(const sim::Sequence& s, int i) {
    sim::RenderBuffers buffers = sim::render_frame(s, i);
    sim::apply_motion_blur(s, i, 0, &buffers);
    sim::SensorFrame sensor = sim::apply_sensor(buffers, s.sensor, s.intrinsics,
                                                s.depth_units_per_m, s.seed, i, s.time_s(i), 0);
    SimFrame f;
    f.image.rgb = sensor.rgb;
    f.image.depth = sensor.depth;
    f.image.depth_units_per_m = s.depth_units_per_m;
    f.image.intrinsics = s.intrinsics;
    f.image.sensor_ns = s.stamp_us(i) * 1000;
    f.image.index = static_cast<uint64_t>(i);
    const sim::Iso3 pose = sim::frame_state(s, i).world_T_camera;
    f.world_T_camera = pose;
    return f;
}

}  // namespace df::test
