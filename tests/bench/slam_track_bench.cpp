// df_bench_slam_track: time of df::slam::track (projective point-to-plane ICP + photometric term,
// 3 levels, 10/5/4 iterations) on a ray-cast synthetic room corner with a box: the model is
// frame A's vertices/normals/colour, the frame is rendered 3 cm / 2.5 deg away. Prints median and
// p95 for 640x480 (pixel step {1,1,1} and {2,1,1}) and 320x240. Convergence ends levels early,
// so --no-early-exit sets the update thresholds to 0 to time every iteration.
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "slam/depth_maps.hpp"
#include "slam/frame.hpp"
#include "slam/tracker.hpp"

namespace {

double texture(const Eigen::Vector3d& p, int surface) {
    const double a = p((surface + 1) % 3), b = p((surface + 2) % 3), ph = 0.7 * surface;
    return 0.5 + 0.22 * std::sin(a / 0.037 + ph) * std::cos(b / 0.03 - ph) +
           0.15 * std::sin((a + 0.6 * b) / 0.013 + 2 * ph);
}

// Room: walls x = 1.2, y = 0.8 (floor, y down), z = 2.0; a 0.4 m box on the floor.
df::io::RgbdImage render(const Eigen::Isometry3d& world_T_camera, int width, int height) {
    df::io::RgbdImage image;
    image.intrinsics = df::slam::scale_intrinsics(df::io::Intrinsics{}, width >= 640 ? 0 : 1);
    image.depth = cv::Mat(height, width, CV_16UC1, cv::Scalar(0));
    image.rgb = cv::Mat(height, width, CV_8UC3, cv::Scalar::all(0));
    const df::io::Intrinsics& k = image.intrinsics;
    const Eigen::Vector3d eye = world_T_camera.translation();
    const Eigen::Vector3d walls(1.2, 0.8, 2.0), box_min(0.45, 0.4, 1.2), box_max(0.85, 0.8, 1.6);
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const Eigen::Vector3d dir =
                world_T_camera.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1);
            double best = std::numeric_limits<double>::infinity();
            int surface = -1;
            for (int i = 0; i < 3; ++i) {
                if (dir(i) <= 1e-12) continue;
                const double t = (walls(i) - eye(i)) / dir(i);
                if (t > 0 && t < best) best = t, surface = i;
            }
            double t_near = -std::numeric_limits<double>::infinity(), t_far = -t_near;
            int face = 0;
            for (int i = 0; i < 3; ++i) {
                double t0 = (box_min(i) - eye(i)) / dir(i), t1 = (box_max(i) - eye(i)) / dir(i);
                if (t0 > t1) std::swap(t0, t1);
                if (t0 > t_near) t_near = t0, face = i;
                t_far = std::min(t_far, t1);
            }
            if (t_near <= t_far && t_near > 0 && t_near < best) best = t_near, surface = 3 + face;
            if (surface < 0) continue;
            const double tex = texture(eye + best * dir, surface);
            image.depth.at<uint16_t>(v, u) =
                static_cast<uint16_t>(std::lround(std::min(best, 13.0) * image.depth_units_per_m));
            const auto g = static_cast<uint8_t>(std::lround(255.0 * tex));
            image.rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(g, static_cast<uint8_t>(255 - g / 2), 90);
        }
    }
    return image;
}

Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
    const Eigen::Vector3d z = (target - eye).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear().col(0) = x;
    pose.linear().col(1) = z.cross(x);
    pose.linear().col(2) = z;
    pose.translation() = eye;
    return pose;
}

int run_case(const char* name, int width, int height, const df::slam::TrackingConfig& config,
             int runs) {
    const Eigen::Isometry3d pose_a = look_at({0, 0, 0}, {1.2, 0.8, 2.0});
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    motion.linear() =
        Eigen::AngleAxisd(2.5 * M_PI / 180, Eigen::Vector3d(0.3, 1, 0.2).normalized()).matrix();
    motion.translation() = Eigen::Vector3d(0.03, -0.02, 0.025);
    const Eigen::Isometry3d pose_b = pose_a * motion;
    const df::io::RgbdImage image_a = render(pose_a, width, height);
    const df::io::RgbdImage image_b = render(pose_b, width, height);
    df::Result<df::slam::Frame> frame_a = df::slam::preprocess(image_a, {});
    df::Result<df::slam::Frame> frame_b = df::slam::preprocess(image_b, {});
    if (!frame_a.is_ok() || !frame_b.is_ok()) {
        std::fprintf(stderr, "preprocess failed\n");
        return 1;
    }
    const df::slam::ModelView model{frame_a->levels[0].vertex, frame_a->levels[0].normal,
                                    image_a.rgb};
    std::vector<double> ms;
    df::slam::TrackingResult last;
    for (int i = 0; i < runs + 3; ++i) {
        const auto start = std::chrono::steady_clock::now();
        df::Result<df::slam::TrackingResult> r =
            df::slam::track(*frame_b, model, pose_a, pose_a, cv::Mat(), config);
        const auto end = std::chrono::steady_clock::now();
        if (!r.is_ok()) {
            std::fprintf(stderr, "track failed: %s\n", r.status().to_string().c_str());
            return 1;
        }
        last = r.value();
        if (i >= 3) ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    std::sort(ms.begin(), ms.end());
    const auto at = [&](double q) {
        return ms[std::min(ms.size() - 1, static_cast<size_t>(q * static_cast<double>(ms.size())))];
    };
    const double err_mm = 1000.0 * (last.world_T_camera.translation() - pose_b.translation()).norm();
    std::printf("track %-22s %dx%d, %d threads, %d runs: median %.2f ms, p95 %.2f ms "
                "(%s, %d iterations, error %.3f mm)\n",
                name, width, height, cv::getNumThreads(), runs, at(0.5), at(0.95),
                df::slam::to_string(last.state), last.iterations, err_mm);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Time of df::slam::track per frame"};
    int runs = 50, threads = 0;
    bool no_early_exit = false;
    app.add_option("--runs", runs, "timed runs per case")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    app.add_option("--threads", threads, "OpenCV threads (0: OpenCV's default)")
        ->capture_default_str();
    app.add_flag("--no-early-exit", no_early_exit, "run every iteration (update thresholds 0)");
    CLI11_PARSE(app, argc, argv);
    if (threads > 0) cv::setNumThreads(threads);

    df::slam::TrackingConfig config;
    if (no_early_exit) {
        config.min_update_translation_m = 0.f;
        config.min_update_rotation_rad = 0.f;
    }
    df::slam::TrackingConfig step2 = config;
    step2.pixel_step = {2, 1, 1};
    df::slam::TrackingConfig icp_only = config;
    icp_only.use_rgb = false;
    int failed = 0;
    failed += run_case("default", 640, 480, config, runs);
    failed += run_case("pixel_step {2,1,1}", 640, 480, step2, runs);
    failed += run_case("icp only", 640, 480, icp_only, runs);
    failed += run_case("default", 320, 240, config, runs);
    return failed == 0 ? 0 : 1;
}
