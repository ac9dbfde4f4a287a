#pragma once
/// Noise-free ray casting of a scene at one instant: depth, instance ids, shaded colour and the
/// per-pixel facts the sensor model needs (incidence angle, material dropout).
#include <opencv2/core.hpp>
#include <vector>

#include "io/rgbd_image.hpp"
#include "sim/scene.hpp"

namespace df::sim {

/// Poses of everything that moves, at one frame.
struct FrameState {
    Iso3 world_T_camera = Iso3::Identity();
    std::vector<ObjectState> objects;  ///< one per Scene::objects, same order
};

struct RenderConfig {
    int width = 640, height = 480;
    io::Intrinsics intrinsics;  ///< pixels; pixel (x, y) looks along ((x-cx)/fx, (y-cy)/fy, 1)
    int threads = 0;            ///< <= 0: all hardware threads
};

struct RenderBuffers {
    cv::Mat depth_m;    ///< CV_32FC1, camera z of the nearest surface, metres
    cv::Mat instance;   ///< CV_16UC1, 0 = static scene, k = Scene::objects[k - 1]
    cv::Mat colour;     ///< CV_32FC3, R,G,B shaded colour, about 0..1
    cv::Mat incidence;  ///< CV_32FC1, cosine between the viewing ray and the surface normal
    cv::Mat dropout;    ///< CV_32FC1, depth_dropout of the surface's material
};

/// Renders the scene as seen by a pinhole camera at state.world_T_camera (must be inside the room).
RenderBuffers render(const Scene& scene, const FrameState& state, const RenderConfig& config);

}  // namespace df::sim
