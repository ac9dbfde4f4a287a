// df_bench_detect: time of df::detect::Detector::detect (default YOLOv5s, CPU) on darknet's
// dog.jpg for several network input sizes; prints median and p95 in ms.
//   df_bench_detect [--image PATH] [--runs N] [--threads N]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "detect/detector.hpp"

int main(int argc, char** argv) {
    CLI::App app{"df_detect speed (YOLOv5s, OpenCV dnn, CPU)"};
    std::string image_path = "/usr/share/darknet/data/dog.jpg";
    int runs = 20;
    int threads = 2;
    app.add_option("--image", image_path, "image to detect on");
    app.add_option("--runs", runs, "timed runs per size (after 2 warm-up runs)");
    app.add_option("--threads", threads, "OpenCV threads");
    CLI11_PARSE(app, argc, argv);

    const cv::Mat image = cv::imread(image_path);
    if (image.empty()) {
        std::fprintf(stderr, "cannot read %s (install Debian's darknet package)\n",
                     image_path.c_str());
        return 1;
    }
    std::printf("df_detect YOLOv5s on %s (%dx%d), %d threads, %d runs\n", image_path.c_str(),
                image.cols, image.rows, threads, runs);
    std::printf("%-9s %10s %10s %s\n", "input", "median_ms", "p95_ms", "detections");
    const std::vector<std::pair<int, int>> sizes = {{320, 320}, {416, 416}, {640, 480}, {640, 640}};
    for (const auto& [w, h] : sizes) {
        df::detect::DetectorConfig config;
        config.input_width = w;
        config.input_height = h;
        config.threads = threads;
        auto detector = df::detect::open_detector(config);
        if (!detector) {
            std::fprintf(stderr, "%s\n(run `bash deploy/setup.sh` if the model is missing)\n",
                         detector.status().to_string().c_str());
            return 1;
        }
        std::vector<double> ms;
        size_t found = 0;
        for (int i = 0; i < runs + 2; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            auto out = (*detector)->detect(image);
            const auto t1 = std::chrono::steady_clock::now();
            if (!out) {
                std::fprintf(stderr, "%s\n", out.status().to_string().c_str());
                return 1;
            }
            found = out->size();
            if (i >= 2) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        }
        std::sort(ms.begin(), ms.end());
        const double median = ms[ms.size() / 2];
        const double p95 = ms[std::min(ms.size() - 1, static_cast<size_t>(0.95 * ms.size()))];
        std::printf("%4dx%-4d %10.1f %10.1f %zu\n", w, h, median, p95, found);
    }
    return 0;
}
