#include "seg/instance_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace df::seg {
namespace {

// Pixels of each segment and the mean of their valid depths.
struct SegmentStats {
    std::vector<int> area;
    std::vector<double> depth_sum;
    std::vector<int> depth_count;
    double mean_depth(int s) const {
        const size_t i = static_cast<size_t>(s);
        return depth_count[i] > 0 ? depth_sum[i] / depth_count[i] : 0.0;
    }
};

SegmentStats segment_stats(const cv::Mat& labels, int count, const cv::Mat& depth_m) {
    SegmentStats st;
    st.area.assign(static_cast<size_t>(count) + 1, 0);
    st.depth_sum.assign(static_cast<size_t>(count) + 1, 0.0);
    st.depth_count.assign(static_cast<size_t>(count) + 1, 0);
    for (int y = 0; y < labels.rows; ++y) {
        const int32_t* l = labels.ptr<int32_t>(y);
        const float* d = depth_m.empty() ? nullptr : depth_m.ptr<float>(y);
        for (int x = 0; x < labels.cols; ++x) {
            const int32_t s = l[x];
            if (s <= 0 || s > count) continue;
            ++st.area[static_cast<size_t>(s)];
            if (d && d[x] > 0.f) {
                st.depth_sum[static_cast<size_t>(s)] += d[x];
                ++st.depth_count[static_cast<size_t>(s)];
            }
        }
    }
    return st;
}

cv::Rect clip_box(const cv::Rect2f& box, cv::Size size) {
    const int x0 = std::max(0, static_cast<int>(std::floor(box.x)));
    const int y0 = std::max(0, static_cast<int>(std::floor(box.y)));
    const int x1 = std::min(size.width, static_cast<int>(std::ceil(box.x + box.width)));
    const int y1 = std::min(size.height, static_cast<int>(std::ceil(box.y + box.height)));
    return x1 > x0 && y1 > y0 ? cv::Rect(x0, y0, x1 - x0, y1 - y0) : cv::Rect();
}

}  // namespace

std::string validate(const InstanceSegmentationConfig& c) {
    return params::check(c);  // ranges: fusion.proto
}

Result<InstanceSegmentation> segment_instances(const cv::Mat& segment_labels, int segment_count,
                                               const cv::Mat& depth_m,
                                               const std::vector<detect::Detection>& detections,
                                               const ClassKindOf& kind_of,
                                               const InstanceSegmentationConfig& config) {
    if (std::string bad = validate(config); !bad.empty()) {
        return error(StatusCode::kInvalidArgument, "InstanceSegmentationConfig: " + bad);
    }
    if (segment_labels.empty() || segment_labels.type() != CV_32SC1 || segment_count < 0) {
        return error(StatusCode::kInvalidArgument,
                     "segment_instances: segment labels must be a non-empty CV_32SC1 image, got " +
                         cv::typeToString(segment_labels.type()));
    }
    if (!depth_m.empty() &&
        (depth_m.type() != CV_32FC1 || depth_m.size() != segment_labels.size())) {
        return error(StatusCode::kInvalidArgument,
                     "segment_instances: depth must be empty or CV_32FC1 of the labels' size");
    }
    const cv::Size size = segment_labels.size();
    const SegmentStats stats = segment_stats(segment_labels, segment_count, depth_m);

    // Boxes of classes that count, smallest first (a small box inside a big one gets its
    // segments before the big one can take them).
    std::vector<size_t> order;
    std::vector<detect::ClassKind> kinds(detections.size(), detect::ClassKind::kIgnored);
    std::vector<cv::Rect> boxes(detections.size());
    for (size_t i = 0; i < detections.size(); ++i) {
        kinds[i] = kind_of ? kind_of(detections[i]) : detect::ClassKind::kRigid;
        boxes[i] = clip_box(detections[i].box, size);
        if (kinds[i] != detect::ClassKind::kIgnored && boxes[i].area() > 0) order.push_back(i);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return boxes[a].area() < boxes[b].area(); });

    std::vector<int> owner(static_cast<size_t>(segment_count) + 1, -1);  // detection index
    std::vector<int> inter(static_cast<size_t>(segment_count) + 1, 0);
    std::vector<int32_t> touched;
    for (size_t i : order) {
        const cv::Rect& box = boxes[i];
        touched.clear();
        for (int y = box.y; y < box.y + box.height; ++y) {
            const int32_t* l = segment_labels.ptr<int32_t>(y);
            for (int x = box.x; x < box.x + box.width; ++x) {
                const int32_t s = l[x];
                if (s <= 0 || s > segment_count || owner[static_cast<size_t>(s)] >= 0) continue;
                if (inter[static_cast<size_t>(s)]++ == 0) touched.push_back(s);
            }
        }
        const double box_area = static_cast<double>(box.area());
        const auto inside_of = [&](int32_t s) {
            return static_cast<double>(inter[static_cast<size_t>(s)]) /
                   stats.area[static_cast<size_t>(s)];
        };
        // The paper's rule: segments whose IoU with the box passes the threshold; the best of
        // them is the core.
        int core = -1;
        double core_iou = 0.0;
        std::vector<int32_t> taken;
        for (int32_t s : touched) {
            const double in = inter[static_cast<size_t>(s)];
            const double iou = in / (stats.area[static_cast<size_t>(s)] + box_area - in);
            if (iou >= config.min_iou) {
                taken.push_back(s);
                if (iou > core_iou) {
                    core_iou = iou;
                    core = s;
                }
            }
        }
        if (config.min_inside_fraction <= 1.f) {
            // An object split by folds (a person's limbs, an occluded car) may have no part that
            // fills the box: then the core is its largest segment lying inside the box, if it
            // covers min_core_box_fraction of it.
            if (core < 0) {
                int best = 0;
                for (int32_t s : touched) {
                    const int in = inter[static_cast<size_t>(s)];
                    if (inside_of(s) >= config.min_inside_fraction && in > best &&
                        in >= config.min_core_box_fraction * box_area) {
                        best = in;
                        core = s;
                    }
                }
                if (core > 0) taken.push_back(core);
            }
            // Last resort: an object merged with its support (a car whose wheels meet the floor
            // without a fold edge) is one segment reaching out of the box; its part inside the
            // box is the mask when it fills min_fill_fraction of the box.
            if (core < 0 && config.min_fill_fraction <= 1.f) {
                int best = 0;
                for (int32_t s : touched) {
                    const int in = inter[static_cast<size_t>(s)];
                    if (in > best && in >= config.min_fill_fraction * box_area) {
                        best = in;
                        core = s;
                    }
                }
                if (core > 0) taken.push_back(core);
            }
            // The other parts: segments inside the box near the core's depth.
            if (core > 0) {
                const double core_depth = stats.mean_depth(core);
                for (int32_t s : touched) {
                    if (std::find(taken.begin(), taken.end(), s) != taken.end()) continue;
                    // Without depth (none given, or none valid) the depth test is skipped.
                    const bool near_core =
                        depth_m.empty() || stats.depth_count[static_cast<size_t>(s)] == 0 ||
                        stats.depth_count[static_cast<size_t>(core)] == 0 ||
                        std::fabs(stats.mean_depth(s) - core_depth) <= config.max_depth_from_core_m;
                    if (inside_of(s) >= config.min_inside_fraction && near_core) {
                        taken.push_back(s);
                    }
                }
            }
        }
        for (int32_t s : touched) inter[static_cast<size_t>(s)] = 0;
        for (int32_t s : taken) owner[static_cast<size_t>(s)] = static_cast<int>(i);
    }

    // Masks: a detection's segments, clipped to its box.
    InstanceSegmentation out;
    out.labels = cv::Mat::zeros(size, CV_16UC1);
    out.rigid_mask = cv::Mat::zeros(size, CV_8UC1);
    out.non_rigid_mask = cv::Mat::zeros(size, CV_8UC1);
    std::vector<int> pixels(detections.size(), 0);
    for (int y = 0; y < size.height; ++y) {
        const int32_t* l = segment_labels.ptr<int32_t>(y);
        for (int x = 0; x < size.width; ++x) {
            const int32_t s = l[x];
            if (s <= 0 || s > segment_count) continue;
            const int d = owner[static_cast<size_t>(s)];
            if (d >= 0 && boxes[static_cast<size_t>(d)].contains(cv::Point(x, y))) {
                ++pixels[static_cast<size_t>(d)];
            }
        }
    }
    std::vector<int> id_of(detections.size(), 0);
    for (size_t i = 0; i < detections.size(); ++i) {
        if (pixels[i] < config.min_instance_pixels || kinds[i] == detect::ClassKind::kIgnored) {
            continue;
        }
        Instance inst;
        inst.id = static_cast<int>(out.instances.size()) + 1;
        inst.detection = detections[i];
        inst.kind = kinds[i];
        inst.pixels = pixels[i];
        id_of[i] = inst.id;
        out.instances.push_back(inst);
    }
    for (int y = 0; y < size.height; ++y) {
        const int32_t* l = segment_labels.ptr<int32_t>(y);
        uint16_t* o = out.labels.ptr<uint16_t>(y);
        uint8_t* rigid = out.rigid_mask.ptr<uint8_t>(y);
        uint8_t* non_rigid = out.non_rigid_mask.ptr<uint8_t>(y);
        for (int x = 0; x < size.width; ++x) {
            const int32_t s = l[x];
            if (s <= 0 || s > segment_count) continue;
            const int d = owner[static_cast<size_t>(s)];
            if (d < 0 || id_of[static_cast<size_t>(d)] == 0 ||
                !boxes[static_cast<size_t>(d)].contains(cv::Point(x, y))) {
                continue;
            }
            o[x] = static_cast<uint16_t>(id_of[static_cast<size_t>(d)]);
            (kinds[static_cast<size_t>(d)] == detect::ClassKind::kNonRigid ? non_rigid : rigid)[x] =
                255;
        }
    }
    return out;
}

}  // namespace df::seg
