#include "sim/simulated_detector.hpp"

#include <algorithm>
#include <random>

namespace df::sim {

std::vector<detect::Detection> simulate_detections(const cv::Mat& instance,
                                                   const std::vector<DynamicObject>& objects,
                                                   int frame,
                                                   const SimulatedDetectorConfig& config) {
    std::vector<ObjectClass> classes;
    for (const DynamicObject& o : objects) classes.push_back({o.class_id, o.class_name});
    return simulate_detections(instance, classes, frame, config);
}

std::vector<detect::Detection> simulate_detections(const cv::Mat& instance,
                                                   const std::vector<ObjectClass>& objects,
                                                   int frame,
                                                   const SimulatedDetectorConfig& config) {
    std::vector<detect::Detection> out;
    if (instance.empty() || instance.type() != CV_16UC1) return out;
    // Bounding box and pixel count per object id.
    const size_t n = objects.size();
    std::vector<int> x0(n + 1, instance.cols), y0(n + 1, instance.rows), x1(n + 1, -1),
        y1(n + 1, -1), count(n + 1, 0);
    for (int y = 0; y < instance.rows; ++y) {
        const uint16_t* row = instance.ptr<uint16_t>(y);
        for (int x = 0; x < instance.cols; ++x) {
            const size_t id = row[x];
            if (id == 0 || id > n) continue;
            x0[id] = std::min(x0[id], x);
            y0[id] = std::min(y0[id], y);
            x1[id] = std::max(x1[id], x);
            y1[id] = std::max(y1[id], y);
            ++count[id];
        }
    }
    std::mt19937_64 rng(config.seed * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(frame));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (size_t id = 1; id <= n; ++id) {
        const ObjectClass& o = objects[id - 1];
        // Draw every random number for every object, so one object's miss does not change
        // another's jitter.
        const double miss = unit(rng);
        const double j[4] = {gauss(rng), gauss(rng), gauss(rng), gauss(rng)};
        if (o.class_id < 0 || count[id] < config.min_visible_pixels) continue;
        if (miss < config.miss_rate) continue;
        const double w = x1[id] - x0[id] + 1, h = y1[id] - y0[id] + 1;
        double l = x0[id] + config.box_jitter * w * j[0];
        double t = y0[id] + config.box_jitter * h * j[1];
        double r = x1[id] + 1 + config.box_jitter * w * j[2];
        double b = y1[id] + 1 + config.box_jitter * h * j[3];
        l = std::clamp(l, 0.0, static_cast<double>(instance.cols));
        r = std::clamp(r, 0.0, static_cast<double>(instance.cols));
        t = std::clamp(t, 0.0, static_cast<double>(instance.rows));
        b = std::clamp(b, 0.0, static_cast<double>(instance.rows));
        if (r - l < 2 || b - t < 2) continue;
        detect::Detection d;
        d.box = cv::Rect2f(static_cast<float>(l), static_cast<float>(t), static_cast<float>(r - l),
                           static_cast<float>(b - t));
        d.class_id = o.class_id;
        d.class_name = o.class_name;
        d.score = static_cast<float>(config.score);
        out.push_back(d);
    }
    std::poisson_distribution<int> false_count(std::max(0.0, config.false_positives_per_frame));
    const int fp = config.false_positives_per_frame > 0 ? false_count(rng) : 0;
    for (int k = 0; k < fp; ++k) {
        const double w = (0.05 + 0.25 * unit(rng)) * instance.cols;
        const double h = (0.05 + 0.25 * unit(rng)) * instance.rows;
        detect::Detection d;
        d.box = cv::Rect2f(static_cast<float>(unit(rng) * (instance.cols - w)),
                           static_cast<float>(unit(rng) * (instance.rows - h)),
                           static_cast<float>(w), static_cast<float>(h));
        std::vector<const ObjectClass*> known;
        for (const ObjectClass& o : objects)
            if (o.class_id >= 0) known.push_back(&o);
        if (known.empty()) {
            d.class_id = 56;
            d.class_name = "chair";
        } else {
            const ObjectClass* o =
                known[static_cast<size_t>(unit(rng) * known.size()) % known.size()];
            d.class_id = o->class_id;
            d.class_name = o->class_name;
        }
        d.score = static_cast<float>(0.3 + 0.3 * unit(rng));
        out.push_back(d);
    }
    return out;
}

}  // namespace df::sim
