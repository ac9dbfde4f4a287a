// df_bench_slam_preprocess: time of df::slam::preprocess (range cut, bilateral filter, 3-level
// pyramid, vertex/normal maps, intensity and gradients) on a synthetic 640x480 frame: a tilted
// plane with a box in front of it, 2 mm noise and a textured colour image. Prints median and p95,
// then the median of each step on its own (the building blocks of depth_maps.hpp and the OpenCV
// calls preprocess makes, run one at a time with the same inputs preprocess gives them).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "slam/depth_maps.hpp"
#include "slam/frame.hpp"

namespace {

df::io::RgbdImage make_frame(int width, int height) {
    df::io::RgbdImage image;
    image.depth = cv::Mat(height, width, CV_16UC1);
    image.rgb = cv::Mat(height, width, CV_8UC3);
    cv::RNG rng(42);
    const df::io::Intrinsics& k = image.intrinsics;
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const double rx = (u - k.cx) / k.fx, ry = (v - k.cy) / k.fy;
            double z = 2.0 / (1.0 - 0.3 * rx - 0.2 * ry);           // tilted wall
            if (std::abs(rx) < 0.2 && std::abs(ry) < 0.2) z = 1.2;  // a box in front
            if ((u / 40 + v / 40) % 7 == 0 && u % 40 < 6) z = 0.0;  // holes
            z += rng.gaussian(0.002);
            image.depth.at<uint16_t>(v, u) =
                z > 0 ? static_cast<uint16_t>(std::lround(z * image.depth_units_per_m)) : 0;
            const auto g =
                static_cast<uint8_t>(128 + 100 * std::sin(u * 0.05) * std::cos(v * 0.07));
            image.rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(g, static_cast<uint8_t>(255 - g), 90);
        }
    }
    return image;
}

/// Times of `run` over `runs` calls after 3 warm-up calls, in ms, sorted.
std::vector<double> time_runs(int runs, const std::function<void()>& run) {
    std::vector<double> ms;
    for (int i = 0; i < runs + 3; ++i) {
        const auto start = std::chrono::steady_clock::now();
        run();
        const auto end = std::chrono::steady_clock::now();
        if (i >= 3) ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms;
}

double quantile(const std::vector<double>& sorted, double q) {
    return sorted[std::min(sorted.size() - 1,
                           static_cast<size_t>(q * static_cast<double>(sorted.size())))];
}

/// Median time of each step of preprocess on its own, on the inputs preprocess gives it.
void print_step_times(const df::io::RgbdImage& image, const df::slam::PreprocessConfig& c,
                      const df::slam::Frame& frame, int runs) {
    using namespace df::slam;
    const FrameLevel& base = frame.levels[0];
    const FrameLevel& level1 = frame.levels[1];
    cv::Mat sink;
    const std::vector<std::pair<std::string, std::function<void()>>> steps = {
        {"depth_to_metres",
         [&] {
             sink = depth_to_metres(image.depth, image.depth_units_per_m, c.min_depth_m,
                                    c.max_depth_m);
         }},
        {"bilateral_filter_depth",
         [&] {
             sink = bilateral_filter_depth(base.depth_m, c.bilateral_sigma_space_px,
                                           c.bilateral_sigma_depth_m, c.bilateral_radius_px);
         }},
        {"rgb_to_intensity", [&] { sink = rgb_to_intensity(image.rgb); }},
        {"compute_vertex_map L0",
         [&] { sink = compute_vertex_map(base.depth_m, base.intrinsics); }},
        {"compute_normal_map L0 (from smoothed depth)",
         [&] { sink = compute_normal_map(base.smoothed_depth_m, base.intrinsics); }},
        {"Sobel x + y L0",
         [&] {
             cv::Sobel(base.intensity, sink, CV_32F, 1, 0, 3, 1.0 / 8.0);
             cv::Sobel(base.intensity, sink, CV_32F, 0, 1, 3, 1.0 / 8.0);
         }},
        {"downsample_depth L0->L1 (x2: raw, smoothed)",
         [&] {
             sink = downsample_depth(base.depth_m, c.pyramid_max_depth_diff_m);
             sink = downsample_depth(base.smoothed_depth_m, c.pyramid_max_depth_diff_m);
         }},
        {"pyrDown intensity L0->L1",
         [&] { cv::pyrDown(base.intensity, sink, level1.depth_m.size()); }},
        {"vertex + normal + Sobel L1",
         [&] {
             sink = compute_vertex_map(level1.depth_m, level1.intrinsics);
             sink =
                 compute_normal_map(compute_vertex_map(level1.smoothed_depth_m, level1.intrinsics));
             cv::Sobel(level1.intensity, sink, CV_32F, 1, 0, 3, 1.0 / 8.0);
             cv::Sobel(level1.intensity, sink, CV_32F, 0, 1, 3, 1.0 / 8.0);
         }},
    };
    for (const auto& [name, run] : steps) {
        std::printf("  %-44s median %6.3f ms\n", name.c_str(), quantile(time_runs(runs, run), 0.5));
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Time of df::slam::preprocess per frame"};
    int frames = 200, width = 640, height = 480, threads = 0;
    app.add_option("--frames", frames, "timed runs")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    app.add_option("--width", width, "image width")->capture_default_str();
    app.add_option("--height", height, "image height")->capture_default_str();
    app.add_option("--threads", threads, "OpenCV threads (0: OpenCV's default)")
        ->capture_default_str();
    bool steps = true;
    app.add_flag("--steps,!--no-steps", steps, "also time each step on its own")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (threads > 0) cv::setNumThreads(threads);

    const df::io::RgbdImage image = make_frame(width, height);
    const df::slam::PreprocessConfig config;
    std::vector<double> ms;
    for (int i = 0; i < frames + 5; ++i) {
        const auto start = std::chrono::steady_clock::now();
        df::Result<df::slam::Frame> frame = df::slam::preprocess(image, config);
        const auto end = std::chrono::steady_clock::now();
        if (!frame.is_ok()) {
            std::fprintf(stderr, "preprocess failed: %s\n", frame.status().to_string().c_str());
            return 1;
        }
        if (i >= 5) ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf(
        "preprocess %dx%d, %d levels, %d OpenCV threads, %d runs: median %.2f ms, p95 %.2f ms\n",
        width, height, config.pyramid_levels, cv::getNumThreads(), frames, quantile(ms, 0.5),
        quantile(ms, 0.95));
    if (steps) print_step_times(image, config, df::slam::preprocess(image, config).value(), frames);
    return 0;
}
