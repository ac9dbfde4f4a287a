// df_bench_seg: time per 640x480 frame of geometric segmentation (one thread) and of the
// box-and-segment fusion, on frames of the generated `default` and `walking_xyz` sequences
// (sensor noise on) with the SIMULATED detector's boxes. Prints median and p95.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <opencv2/core/utility.hpp>
#include <vector>

#include "seg/geometric_segmentation.hpp"
#include "seg/instance_segmentation.hpp"
#include "sim/render.hpp"
#include "sim/sensor.hpp"
#include "sim/sequence.hpp"
#include "sim/simulated_detector.hpp"
#include "slam/frame.hpp"

namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

void print(const char* what, std::vector<double> v) {
    std::sort(v.begin(), v.end());
    std::printf("%-44s median %6.2f ms  p95 %6.2f ms  (%zu runs)\n", what, v[v.size() / 2],
                v[std::min(v.size() - 1, v.size() * 95 / 100)], v.size());
}

}  // namespace

int main() {
    using namespace df;
    cv::setNumThreads(1);  // the target is one core
    std::vector<double> geometric, fusion;
    for (const char* preset : {"default", "walking_xyz"}) {
        sim::PresetOptions options;
        options.noise = true;
        auto s = sim::make_sequence(preset, options);
        if (!s) {
            std::fprintf(stderr, "%s\n", s.status().message().c_str());
            return 1;
        }
        for (int i = 10; i < 120; i += 10) {
            const sim::RenderBuffers b = sim::render_frame(*s, i);
            const sim::SensorFrame sensor = sim::apply_sensor(
                b, s->sensor, s->intrinsics, s->depth_units_per_m, s->seed, i, s->time_s(i), 0);
            io::RgbdImage image;
            image.rgb = sensor.rgb;
            image.depth = sensor.depth;
            image.depth_units_per_m = s->depth_units_per_m;
            image.intrinsics = s->intrinsics;
            auto frame = slam::preprocess(image, slam::PreprocessConfig{});
            if (!frame) return 1;
            const slam::FrameLevel& l = frame->levels[0];
            const auto dets = sim::simulate_detections(b.instance, s->scene.objects, i, {});
            for (int run = 0; run < 3; ++run) {
                auto t = std::chrono::steady_clock::now();
                auto g = seg::segment_geometry(l.smoothed_vertex, l.normal);
                geometric.push_back(ms_since(t));
                if (!g) return 1;
                t = std::chrono::steady_clock::now();
                auto r = seg::segment_instances(g->labels, g->count, l.depth_m, dets, nullptr);
                fusion.push_back(ms_since(t));
                if (!r) return 1;
            }
        }
    }
    std::printf("640x480, one thread:\n");
    print("geometric segmentation (edges, components)", geometric);
    print("object masks (box-and-segment fusion)", fusion);
    return 0;
}
