#pragma once
// Ray-cast RGB-D views of scenes made of infinite planes and axis-aligned boxes, whose depth,
// normals and colours are known exactly (tests of df_map).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "io/rgbd_image.hpp"

namespace df::map::testing {

/// Pinhole intrinsics with f = width (about 53 degrees across) and a centred principal point.
inline io::Intrinsics intrinsics_for(int width, int height) {
    const double f = width;
    return {f, f, 0.5 * (width - 1), 0.5 * (height - 1)};
}

/// The plane normal . X = offset (world frame, metres). Its colour varies along world x and y
/// (red = 128 + 200 x, green = 128 + 200 y, clamped) so that colour prediction can be checked.
struct Plane {
    Eigen::Vector3f normal;
    float offset;
    uint8_t blue;
};

/// An axis-aligned box (world frame, metres) of one colour.
struct Box {
    Eigen::Vector3f min, max;
    cv::Vec3b colour;
};

struct Scene {
    std::vector<Plane> planes;
    std::vector<Box> boxes;
};

/// Vertex (camera frame, metres), normal (camera frame, towards the camera) and R,G,B maps;
/// pixels whose ray hits nothing are (0,0,0) everywhere.
struct View {
    cv::Mat vertex, normal, rgb;
};

inline cv::Vec3b plane_colour(const Eigen::Vector3f& world, uint8_t blue) {
    const auto channel = [](float value) {
        return static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
    };
    return {channel(128.f + 200.f * world.x()), channel(128.f + 200.f * world.y()), blue};
}

inline View render(const Scene& scene, const Eigen::Isometry3f& world_T_camera, int width,
                   int height) {
    const io::Intrinsics k = intrinsics_for(width, height);
    View view{cv::Mat(height, width, CV_32FC3, cv::Scalar::all(0)),
              cv::Mat(height, width, CV_32FC3, cv::Scalar::all(0)),
              cv::Mat(height, width, CV_8UC3, cv::Scalar::all(0))};
    const Eigen::Matrix3f world_R_camera = world_T_camera.linear();
    const Eigen::Vector3f origin = world_T_camera.translation();
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            // Camera ray (x, y, 1): the parameter t of a hit is its camera-frame depth.
            const Eigen::Vector3f ray(static_cast<float>((u - k.cx) / k.fx),
                                      static_cast<float>((v - k.cy) / k.fy), 1.f);
            const Eigen::Vector3f dir = world_R_camera * ray;
            float best = std::numeric_limits<float>::infinity();
            Eigen::Vector3f normal = Eigen::Vector3f::Zero();
            cv::Vec3b colour;
            for (const Plane& plane : scene.planes) {
                const float denom = plane.normal.dot(dir);
                if (std::abs(denom) < 1e-6f) continue;
                const float t = (plane.offset - plane.normal.dot(origin)) / denom;
                if (t > 0.f && t < best) {
                    best = t;
                    normal = plane.normal;
                    colour = plane_colour(origin + t * dir, plane.blue);
                }
            }
            for (const Box& box : scene.boxes) {
                float t_near = 0.f, t_far = std::numeric_limits<float>::infinity();
                int axis = -1;
                for (int a = 0; a < 3; ++a) {
                    if (std::abs(dir[a]) < 1e-9f) {
                        if (origin[a] < box.min[a] || origin[a] > box.max[a]) t_near = t_far + 1.f;
                        continue;
                    }
                    float t0 = (box.min[a] - origin[a]) / dir[a];
                    float t1 = (box.max[a] - origin[a]) / dir[a];
                    if (t0 > t1) std::swap(t0, t1);
                    if (t0 > t_near) {
                        t_near = t0;
                        axis = a;
                    }
                    t_far = std::min(t_far, t1);
                }
                if (axis >= 0 && t_near <= t_far && t_near > 0.f && t_near < best) {
                    best = t_near;
                    normal = Eigen::Vector3f::Unit(axis);
                    colour = box.colour;
                }
            }
            if (!std::isfinite(best)) continue;
            Eigen::Vector3f normal_cam = world_R_camera.transpose() * normal;
            if (normal_cam.dot(ray) > 0.f) normal_cam = -normal_cam;
            const Eigen::Vector3f p = best * ray;
            view.vertex.at<cv::Vec3f>(v, u) = {p.x(), p.y(), p.z()};
            view.normal.at<cv::Vec3f>(v, u) = {normal_cam.x(), normal_cam.y(), normal_cam.z()};
            view.rgb.at<cv::Vec3b>(v, u) = colour;
        }
    }
    return view;
}

}  // namespace df::map::testing
