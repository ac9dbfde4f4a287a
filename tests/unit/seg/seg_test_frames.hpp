#pragma once
// Frames of generated sequences (sensor noise on) as the segmentation sees them: df_slam's
// preprocessing (smoothed vertices, normals) plus the ground-truth instance image; and the
// scores of a segmentation against that truth.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "sim/render.hpp"
#include "sim/sensor.hpp"
#include "sim/sequence.hpp"
#include "slam/frame.hpp"

namespace df::test {

struct SegFrame {
    int index = 0;
    cv::Mat vertex, normal, depth_m;  // camera frame, df_slam level 0
    cv::Mat instance;                 // CV_16UC1, 0 = static scene, k = objects[k - 1]
};

struct SegFrames {
    sim::Sequence sequence;
    std::map<int, std::string> names;  // instance id -> object name
    std::vector<SegFrame> frames;
};

inline SegFrames seg_frames(const std::string& preset, const std::vector<int>& indices) {
    SegFrames out;
    sim::PresetOptions options;
    options.noise = true;
    auto s = sim::make_sequence(preset, options);
    EXPECT_TRUE(s.is_ok()) << s.status().message();
    out.sequence = *s;
    for (size_t k = 0; k < s->scene.objects.size(); ++k)
        out.names[static_cast<int>(k) + 1] = s->scene.objects[k].name;
    for (int i : indices) {
        const sim::RenderBuffers buffers = sim::render_frame(*s, i);
        const sim::SensorFrame sensor = sim::apply_sensor(
            buffers, s->sensor, s->intrinsics, s->depth_units_per_m, s->seed, i, s->time_s(i), 0);
        io::RgbdImage image;
        image.rgb = sensor.rgb;
        image.depth = sensor.depth;
        image.depth_units_per_m = s->depth_units_per_m;
        image.intrinsics = s->intrinsics;
        auto frame = slam::preprocess(image, slam::PreprocessConfig{});
        EXPECT_TRUE(frame.is_ok()) << frame.status().message();
        SegFrame f;
        f.index = i;
        f.vertex = frame->levels[0].smoothed_vertex;
        f.normal = frame->levels[0].normal;
        f.depth_m = frame->levels[0].depth_m;
        f.instance = buffers.instance;
        out.frames.push_back(f);
    }
    return out;
}

/// Median depth (metres) of the pixels of instance `id` in `depth_m`, 0 if none is valid.
inline double median_depth(const cv::Mat& instance, const cv::Mat& depth_m, int id) {
    std::vector<float> z;
    for (int y = 0; y < instance.rows; ++y)
        for (int x = 0; x < instance.cols; ++x)
            if (instance.at<uint16_t>(y, x) == id && depth_m.at<float>(y, x) > 0.f)
                z.push_back(depth_m.at<float>(y, x));
    if (z.empty()) return 0.0;
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    return z[z.size() / 2];
}

/// Objects are scored within this depth (median of their pixels): beyond it Kinect-like noise
/// (sigma ~ 1.4 mm z^2) makes normals too coarse for any fold test (the SLAM tracks to 4 m).
constexpr double kMaxScoredDepthM = 3.5;

/// Per visible object (>= 1000 ground-truth pixels): the IoU of the segment that overlaps it
/// best. Also (straddling, object segments): segments with >= 10 % of their pixels on one
/// object, and of those, how many have >= 10 % elsewhere (background or another object).
inline std::pair<std::map<int, double>, std::pair<int, int>> best_segment_ious(
    const cv::Mat& labels, int count, const cv::Mat& instance) {
    std::map<std::pair<int, int>, int> inter;  // (segment, id) -> pixels
    std::map<int, int> seg_area, id_area;
    for (int y = 0; y < labels.rows; ++y)
        for (int x = 0; x < labels.cols; ++x) {
            const int s = labels.at<int32_t>(y, x), id = instance.at<uint16_t>(y, x);
            ++id_area[id];
            if (s <= 0) continue;
            ++seg_area[s];
            ++inter[{s, id}];
        }
    std::map<int, double> best;
    for (const auto& [id, area] : id_area)
        if (id != 0 && area >= 1000) best[id] = 0.0;  // no overlapping segment: IoU 0
    for (const auto& [key, n] : inter) {
        const auto [s, id] = key;
        if (id == 0 || id_area[id] < 1000) continue;
        const double iou = n / static_cast<double>(seg_area[s] + id_area[id] - n);
        best[id] = std::max(best[id], iou);
    }
    int straddling = 0, object_segments = 0;
    for (int s = 1; s <= count; ++s) {
        const double area = seg_area[s];
        if (area < 1) continue;
        for (const auto& [key, n] : inter) {
            if (key.first != s || key.second == 0 || n < 0.1 * area) continue;
            ++object_segments;
            if (area - n >= 0.1 * area) ++straddling;
            break;
        }
    }
    return {best, {straddling, object_segments}};
}

/// Segments that straddle a depth discontinuity between an object and the background (or another
/// object): at least `min_pairs` pairs of 4-neighbour pixels inside the segment whose ground-truth
/// ids differ and whose depths differ by more than `min_step_m`. 10 cm: where an object stands
/// on the floor, its lowest pixels and the floor just behind differ by 5-7 cm without any gap (a
/// contact, not a discontinuity; at 2-3 m that is also 3 sigma of Kinect-like noise).
inline int segments_across_depth_steps(const cv::Mat& labels, const cv::Mat& instance,
                                       const cv::Mat& depth_m, double min_step_m = 0.10,
                                       int min_pairs = 10) {
    std::map<int, int> pairs;
    for (int y = 0; y + 1 < labels.rows; ++y)
        for (int x = 0; x + 1 < labels.cols; ++x) {
            const int s = labels.at<int32_t>(y, x);
            if (s <= 0) continue;
            const int id = instance.at<uint16_t>(y, x);
            const float z = depth_m.at<float>(y, x);
            for (const auto& [nx, ny] : {std::pair{x + 1, y}, std::pair{x, y + 1}}) {
                if (labels.at<int32_t>(ny, nx) != s || instance.at<uint16_t>(ny, nx) == id)
                    continue;
                const float zn = depth_m.at<float>(ny, nx);
                if (z > 0.f && zn > 0.f && std::fabs(zn - z) > min_step_m) ++pairs[s];
            }
        }
    int n = 0;
    for (const auto& [s, count] : pairs) n += count >= min_pairs;
    return n;
}

}  // namespace df::test
