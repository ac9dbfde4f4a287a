// df_bench_slam_preprocess: time of df::slam::preprocess (range cut, bilateral filter, 3-level
// pyramid, vertex/normal maps, intensity and gradients) on a synthetic 640x480 frame: a tilted
// plane with a box in front of it, 2 mm noise and a textured colour image. Prints median and p95.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <vector>

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
    const auto at = [&](double q) {
        return ms[std::min(ms.size() - 1, static_cast<size_t>(q * static_cast<double>(ms.size())))];
    };
    std::printf(
        "preprocess %dx%d, %d levels, %d OpenCV threads, %d runs: median %.2f ms, p95 %.2f ms\n",
        width, height, config.pyramid_levels, cv::getNumThreads(), frames, at(0.5), at(0.95));
    return 0;
}
