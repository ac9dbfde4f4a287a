// df_bench_map_fuse: time of SurfelMap::fuse() on 640x480 frames of a noisy plane (the first
// frame creates every surfel, later ones merge), median and p95 over the later frames.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "map/surfel_map.hpp"

int main() {
    using namespace df::map;
    const int w = 640, h = 480, frames = 30;
    const PinholeIntrinsics k{535.4f, 539.2f, 320.1f, 247.6f};
    std::mt19937 rng(1);
    std::normal_distribution<float> noise(0.f, 0.003f);
    SurfelMap map;
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
        cv::Mat vertex(h, w, CV_32FC3), normal(h, w, CV_32FC3),
            rgb(h, w, CV_8UC3, cv::Scalar(90, 120, 150));
        for (int v = 0; v < h; ++v) {
            for (int u = 0; u < w; ++u) {
                const float z = 1.5f + noise(rng);
                vertex.at<cv::Vec3f>(v, u) = {(u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z};
                normal.at<cv::Vec3f>(v, u) = {0.f, 0.f, -1.f};
            }
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto stats =
            map.fuse(vertex, normal, rgb, {}, {}, Eigen::Isometry3f::Identity(), k, f);
        const double t =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        if (!stats) return std::fprintf(stderr, "%s\n", stats.status().to_string().c_str()), 1;
        if (f == 0)
            std::printf("first frame (creates %zu surfels): %.2f ms\n", stats->created, t);
        else
            ms.push_back(t);
    }
    std::sort(ms.begin(), ms.end());
    std::printf(
        "fuse 640x480 into a map of %zu surfels: median %.2f ms, p95 %.2f ms (%zu frames)\n",
        map.size(), ms[ms.size() / 2], ms[static_cast<size_t>(0.95 * (ms.size() - 1))], ms.size());
    return 0;
}
