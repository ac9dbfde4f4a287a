// df_bench_map_fuse: time of SurfelMap::fuse() on 640x480 frames of a noisy plane (the first
// frame creates every surfel, later ones merge), median and p95 over the later frames; then the
// time of SurfelMap::predict() of that map at 640x480 from poses around the fusing one (splatted
// and one pixel per surfel), median and p95.
// Usage: df_bench_map_fuse [threads]   (predict's worker threads; 0 or absent = all)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "map/surfel_map.hpp"

namespace {

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void print_figures(const char* what, std::vector<double> ms, const char* tail) {
    std::sort(ms.begin(), ms.end());
    std::printf("%s: median %.2f ms, p95 %.2f ms (%zu runs)%s\n", what, ms[ms.size() / 2],
                ms[static_cast<size_t>(0.95 * static_cast<double>(ms.size() - 1))], ms.size(),
                tail);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace df::map;
    const int w = 640, h = 480, frames = 30, predictions = 40;
    const int threads = argc > 1 ? std::atoi(argv[1]) : 0;
    const df::io::Intrinsics k{535.4, 539.2, 320.1, 247.6};
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    std::mt19937 rng(1);
    std::normal_distribution<float> noise(0.f, 0.003f);
    SurfelMap map;
    std::vector<double> fuse_ms;
    for (int f = 0; f < frames; ++f) {
        cv::Mat vertex(h, w, CV_32FC3), normal(h, w, CV_32FC3),
            rgb(h, w, CV_8UC3, cv::Scalar(90, 120, 150));
        for (int v = 0; v < h; ++v) {
            for (int u = 0; u < w; ++u) {
                const float z = 1.5f + noise(rng);
                vertex.at<cv::Vec3f>(v, u) = {(u - cx) / fx * z, (v - cy) / fy * z, z};
                normal.at<cv::Vec3f>(v, u) = {0.f, 0.f, -1.f};
            }
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto stats =
            map.fuse(vertex, normal, rgb, {}, {}, Eigen::Isometry3f::Identity(), k, f);
        const double t = elapsed_ms(t0);
        if (!stats) return std::fprintf(stderr, "%s\n", stats.status().to_string().c_str()), 1;
        if (f == 0)
            std::printf("first frame (creates %zu surfels): %.2f ms\n", stats->created, t);
        else
            fuse_ms.push_back(t);
    }
    char tail[128];
    std::snprintf(tail, sizeof(tail), ", map of %zu surfels", map.size());
    print_figures("fuse 640x480", fuse_ms, tail);

    // predict_into reuses its images (as a tracker that keeps them does); predict() allocates
    // them on every call.
    struct Mode {
        const char* name;
        bool splat, reuse;
    };
    for (const Mode mode : {Mode{"predict_into 640x480 splat", true, true},
                            Mode{"predict 640x480 splat (new images)", true, false},
                            Mode{"predict_into 640x480 points", false, true}}) {
        PredictionConfig config;
        config.splat = mode.splat;
        config.threads = threads;
        ModelPrediction kept;
        std::vector<double> predict_ms;
        size_t seen = 0;
        for (int i = 0; i < predictions; ++i) {
            // Poses within a few centimetres and a degree of the fusing one, as in tracking.
            Eigen::Isometry3f world_T_camera = Eigen::Isometry3f::Identity();
            const float s = static_cast<float>(i % 8) / 8.f - 0.5f;
            world_T_camera.translation() = Eigen::Vector3f(0.04f * s, -0.02f * s, 0.05f * s);
            world_T_camera.linear() =
                Eigen::AngleAxisf(0.017f * s, Eigen::Vector3f(0.f, 1.f, 0.f)).toRotationMatrix();
            const auto t0 = std::chrono::steady_clock::now();
            df::Status status = df::Status::ok();
            if (mode.reuse) {
                status = map.predict_into(world_T_camera, k, w, h, frames, config, kept);
            } else {
                auto prediction = map.predict(world_T_camera, k, w, h, frames, config);
                if (prediction)
                    kept = std::move(*prediction);
                else
                    status = prediction.status();
            }
            predict_ms.push_back(elapsed_ms(t0));
            if (!status.is_ok()) return std::fprintf(stderr, "%s\n", status.to_string().c_str()), 1;
            seen += static_cast<size_t>(cv::countNonZero(kept.index >= 0));
        }
        std::snprintf(tail, sizeof(tail), ", %zu surfels, threads %d, %.1f %% pixels covered",
                      map.size(), threads,
                      100.0 * static_cast<double>(seen) / (double(predictions) * w * h));
        print_figures(mode.name, predict_ms, tail);
    }
    return 0;
}
