// df_make_demo_data: renders a small synthetic TUM RGB-D sequence with ground truth.
//
// PLACEHOLDER DATA: a ray-cast box room with one box inside and a smoothly moving camera, so the
// pipeline can run without downloading anything. It has no noise, no lighting model worth the
// name and no moving objects; replace it with a proper generator (common/sim) when one exists.
//
// Output (TUM layout, fr3 intrinsics 535.4 539.2 320.1 247.6, 640x480, 30 Hz stamps from 1.0 s):
//   rgb/, depth/ (16-bit, 5000 units per metre), rgb.txt, depth.txt, associations.txt,
//   groundtruth.txt (world_T_camera).
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "io/tum/trajectory.hpp"
#include "io/tum/tum_folder.hpp"

namespace {

using Eigen::Vector3d;

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr double kFps = 30.0;
constexpr double kFirstStampS = 1.0;
constexpr double kDepthUnitsPerM = 5000.0;
constexpr double kPi = 3.14159265358979323846;

struct Box {
    Vector3d min, max;
};

/// The scene in world coordinates (x right, y down, z forward, metres).
struct Scene {
    Box room{{-2.5, -1.4, -1.0}, {2.5, 1.1, 5.0}};
    Box object;
    uint32_t seed = 1;
};

/// Deterministic hash of integers to [0, 1).
double hash01(uint32_t seed, int64_t a, int64_t b, int64_t c) {
    uint64_t h = seed * 0x9E3779B97F4A7C15ull;
    for (int64_t v : {a, b, c}) {
        h ^= static_cast<uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h ^= h >> 33;
        h *= 0xFF51AFD7ED558CCDull;
        h ^= h >> 33;
    }
    return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

/// Colour (0..1, R,G,B) of a surface point with in-plane coordinates (u, v) in metres.
Vector3d texture(const Scene& scene, int surface, double u, double v) {
    static const Vector3d kBase[] = {
        {0.85, 0.55, 0.45}, {0.45, 0.65, 0.85}, {0.80, 0.80, 0.70},  // walls -x, +x, ceiling
        {0.55, 0.45, 0.35}, {0.60, 0.80, 0.55}, {0.75, 0.60, 0.80},  // floor, back, front
        {0.95, 0.30, 0.20}};                                         // the object
    // Tiles give strong edges; hashed cells inside them give corners to track.
    const int64_t tu = static_cast<int64_t>(std::floor(u / 0.4));
    const int64_t tv = static_cast<int64_t>(std::floor(v / 0.4));
    const double checker = ((tu + tv) & 1) ? 0.75 : 1.0;
    const int64_t cu = static_cast<int64_t>(std::floor(u / 0.08));
    const int64_t cv = static_cast<int64_t>(std::floor(v / 0.08));
    const double speckle = 0.65 + 0.35 * hash01(scene.seed, cu, cv, surface);
    Vector3d colour = kBase[surface] * checker * speckle;
    if (surface == 6 && std::fmod(std::abs(u + v), 0.2) < 0.07) colour = {0.95, 0.90, 0.20};
    return colour;
}

struct Hit {
    double depth = 0;  ///< along the ray with unit camera z, i.e. camera z-depth in metres
    Vector3d colour = Vector3d::Zero();
};

/// Casts a ray from `origin` along `dir` (world) and returns the nearest surface.
Hit cast(const Scene& scene, const Vector3d& origin, const Vector3d& dir) {
    // Inside the room the ray leaves through the face of the smallest exit distance.
    double t_exit = INFINITY;
    int exit_axis = 0;
    for (int i = 0; i < 3; ++i) {
        if (dir[i] == 0) continue;
        const double wall = dir[i] > 0 ? scene.room.max[i] : scene.room.min[i];
        const double t = (wall - origin[i]) / dir[i];
        if (t < t_exit) {
            t_exit = t;
            exit_axis = i;
        }
    }
    // Slab test against the object.
    double t_near = -INFINITY, t_far = INFINITY;
    int near_axis = 0;
    for (int i = 0; i < 3; ++i) {
        if (dir[i] == 0) {
            if (origin[i] < scene.object.min[i] || origin[i] > scene.object.max[i]) t_far = -1;
            continue;
        }
        double t0 = (scene.object.min[i] - origin[i]) / dir[i];
        double t1 = (scene.object.max[i] - origin[i]) / dir[i];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_near) {
            t_near = t0;
            near_axis = i;
        }
        t_far = std::min(t_far, t1);
    }
    const bool hits_object = t_near <= t_far && t_near > 0 && t_near < t_exit;
    const double t = hits_object ? t_near : t_exit;
    const int axis = hits_object ? near_axis : exit_axis;
    const Vector3d p = origin + t * dir;
    const int u_axis = axis == 0 ? 2 : 0, v_axis = axis == 1 ? 2 : 1;
    // Room faces: 0 -x, 1 +x, 2 ceiling (-y), 3 floor (+y), 4 near (-z), 5 far (+z); 6 object.
    const int surface = hits_object ? 6 : 2 * axis + (dir[axis] > 0 ? 1 : 0);
    Hit hit;
    hit.depth = t;
    Vector3d normal = Vector3d::Zero();
    normal[axis] = dir[axis] > 0 ? -1 : 1;  // facing the camera
    const Vector3d light(0.0, -1.2, 1.5);
    const double lambert = std::max(0.0, normal.dot((light - p).normalized()));
    hit.colour = texture(scene, surface, p[u_axis], p[v_axis]) * (0.45 + 0.55 * lambert);
    return hit;
}

/// world_T_camera at time s: a smooth sweep with a little rotation, looking down at the object.
Eigen::Isometry3d camera_pose(double s, uint32_t seed) {
    const double w = 2.0 * kPi / 6.0;  // one loop per 6 s, whatever the number of frames
    const double phase = 2.0 * kPi * hash01(seed, 7, 0, 0);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() =
        Vector3d(0.5 * std::sin(w * s), -0.08 * std::sin(2 * w * s), 0.4 * (1.0 - std::cos(w * s)));
    const double yaw = 0.15 * std::sin(w * s + phase);
    const double pitch = -0.30 + 0.05 * std::sin(2 * w * s);  // negative: looking down (+y)
    const double roll = 0.03 * std::sin(w * s);
    pose.linear() =
        (Eigen::AngleAxisd(yaw, Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Vector3d::UnitX()) *
         Eigen::AngleAxisd(roll, Vector3d::UnitZ()))
            .toRotationMatrix();
    return pose;
}

df::io::RgbdImage render(const Scene& scene, const Eigen::Isometry3d& world_T_camera,
                         const df::io::Intrinsics& k) {
    df::io::RgbdImage image;
    image.rgb.create(kHeight, kWidth, CV_8UC3);
    image.depth.create(kHeight, kWidth, CV_16UC1);
    image.intrinsics = k;
    image.depth_units_per_m = kDepthUnitsPerM;
    const Eigen::Matrix3d r = world_T_camera.linear();
    const Vector3d origin = world_T_camera.translation();
    cv::parallel_for_(cv::Range(0, kHeight), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            auto* rgb = image.rgb.ptr<cv::Vec3b>(y);
            auto* depth = image.depth.ptr<uint16_t>(y);
            for (int x = 0; x < kWidth; ++x) {
                const Vector3d ray_camera((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
                const Hit hit = cast(scene, origin, r * ray_camera);
                const double raw = std::round(hit.depth * kDepthUnitsPerM);
                depth[x] = raw > 0 && raw < 65535 ? static_cast<uint16_t>(raw) : 0;
                for (int c = 0; c < 3; ++c) {
                    rgb[x][c] = cv::saturate_cast<uint8_t>(255.0 * hit.colour[c]);
                }
            }
        }
    });
    return image;
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("make_demo_data");
    CLI::App app{"Renders a small synthetic TUM RGB-D sequence (placeholder demo data)"};
    std::string out;
    int frames = 90;
    uint32_t seed = 1;
    app.add_option("--out", out, "output folder (created)")->required();
    app.add_option("--frames", frames, "number of frames at 30 Hz")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    app.add_option("--seed", seed, "texture and motion seed")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    df::log::info("rendering ", frames, " frames (seed ", seed, ", fr3 intrinsics, ", kWidth, "x",
                  kHeight, ") to ", out);

    try {
        Scene scene;
        scene.seed = seed;
        const double ox = -0.6 + 1.2 * hash01(seed, 1, 0, 0);
        const double oz = 2.2 + 0.8 * hash01(seed, 2, 0, 0);
        scene.object = {{ox - 0.35, 0.5, oz - 0.3}, {ox + 0.35, 1.1, oz + 0.3}};  // on the floor

        const df::io::Intrinsics intrinsics = df::io::intrinsics_preset("fr3").value();
        std::vector<df::io::RgbdImage> images;
        std::vector<df::io::StampedPose> truth;
        for (int i = 0; i < frames; ++i) {
            // Stamps are whole microseconds so the file names, lists and ground truth agree.
            const int64_t stamp_us = std::llround((kFirstStampS + i / kFps) * 1e6);
            const double s = i / kFps;
            const Eigen::Isometry3d world_T_camera = camera_pose(s, seed);
            df::io::RgbdImage image = render(scene, world_T_camera, intrinsics);
            image.sensor_ns = stamp_us * 1000;
            image.index = static_cast<uint64_t>(i);
            images.push_back(std::move(image));
            truth.push_back({static_cast<double>(stamp_us) * 1e-6, world_T_camera.translation(),
                             Eigen::Quaterniond(world_T_camera.linear())});
        }
        df::Status status = df::io::write_tum_folder(out, images);
        if (status) status = df::io::write_tum_trajectory(out + "/groundtruth.txt", truth);
        if (!status) {
            df::log::error(status.to_string());
            return 1;
        }
    } catch (const cv::Exception& e) {
        df::log::error("OpenCV: ", e.what());
        return 1;
    }
    df::log::info("wrote ", frames, " frames and groundtruth.txt to ", out);
    return 0;
}
