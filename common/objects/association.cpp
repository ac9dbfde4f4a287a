#include "objects/association.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <tuple>

namespace df::objects {

std::string validate(const AssociationConfig& c) { return params::check(c); }

std::vector<uint16_t> explained_by_background(const dynamics::LabelImage& instances,
                                              const Association& association,
                                              const cv::Mat& depth_m,
                                              const cv::Mat& background_depth_m, float fraction,
                                              const AssociationConfig& config) {
    std::vector<uint16_t> out;
    if (association.unmatched_rigid.empty() || instances.labels.empty() ||
        background_depth_m.size() != depth_m.size() || instances.labels.size() != depth_m.size())
        return out;
    std::map<uint16_t, std::pair<int, int>> counts;  // id -> (with depth, explained)
    for (uint16_t id : association.unmatched_rigid) counts[id] = {0, 0};
    for (int v = 0; v < depth_m.rows; ++v) {
        const uint16_t* l = instances.labels.ptr<uint16_t>(v);
        const float* d = depth_m.ptr<float>(v);
        const float* b = background_depth_m.ptr<float>(v);
        for (int u = 0; u < depth_m.cols; ++u) {
            if (l[u] == 0 || !(d[u] > 0.f)) continue;
            auto it = counts.find(l[u]);
            if (it == counts.end()) continue;
            ++it->second.first;
            if (agrees_with_background(d[u], b[u], config)) ++it->second.second;
        }
    }
    for (const auto& [id, c] : counts)
        if (c.first > 0 && static_cast<float>(c.second) >= fraction * static_cast<float>(c.first))
            out.push_back(id);
    return out;
}

float box_iou(const cv::Rect2f& a, const cv::Rect2f& b) {
    if (a.area() <= 0.f || b.area() <= 0.f) return 0.f;
    const float inter = (a & b).area();
    return inter / (a.area() + b.area() - inter);
}

Association associate(const dynamics::LabelImage& instances, const std::vector<ObjectView>& views,
                      const cv::Mat& depth_m, const AssociationConfig& config,
                      const cv::Mat& background_depth_m) {
    const bool background =
        !background_depth_m.empty() && background_depth_m.size() == depth_m.size();
    const cv::Size size = depth_m.size();
    const int n = static_cast<int>(views.size());
    Association out;
    out.instance_of_view.assign(static_cast<size_t>(n), 0);
    out.pixels_of_view.assign(static_cast<size_t>(n), 0);
    out.silhouette_pixels_of_view.assign(static_cast<size_t>(n), 0);
    out.view_labels = cv::Mat::zeros(size, CV_16UC1);

    // The nearest rendered surface per pixel: which view's silhouette it is (index + 1).
    cv::Mat nearest = cv::Mat::zeros(size, CV_16UC1);
    cv::Mat nearest_z(size, CV_32F, cv::Scalar(0.f));
    for (int k = 0; k < n; ++k) {
        const cv::Mat& z = views[static_cast<size_t>(k)].depth_m;
        if (z.empty() || z.size() != size) continue;
        for (int v = 0; v < size.height; ++v) {
            const float* zr = z.ptr<float>(v);
            float* nz = nearest_z.ptr<float>(v);
            uint16_t* nl = nearest.ptr<uint16_t>(v);
            for (int u = 0; u < size.width; ++u) {
                if (zr[u] > 0.f && (nz[u] == 0.f || zr[u] < nz[u])) {
                    nz[u] = zr[u];
                    nl[u] = static_cast<uint16_t>(k + 1);
                }
            }
        }
    }

    // Per (instance, view): pixels of the instance inside the view's silhouette.
    const bool have_labels = !instances.labels.empty() && instances.labels.size() == size;
    std::map<uint16_t, int> instance_pixels;
    std::map<std::pair<uint16_t, int>, int> overlap;
    std::map<uint16_t, bool> claimable;  // id -> may a silhouette take its pixels
    for (const dynamics::InstanceInfo& row : instances.instances)
        claimable[row.id] = row.kind == dynamics::ObjectKind::kRigid;
    if (have_labels) {
        for (int v = 0; v < size.height; ++v) {
            const uint16_t* l = instances.labels.ptr<uint16_t>(v);
            const uint16_t* s = nearest.ptr<uint16_t>(v);
            for (int u = 0; u < size.width; ++u) {
                if (l[u] == 0) continue;
                ++instance_pixels[l[u]];
                if (s[u] != 0) ++overlap[{l[u], s[u] - 1}];
            }
        }
    }
    // Greedy by decreasing overlap fraction.
    std::vector<std::tuple<float, uint16_t, int>> pairs;
    for (const auto& [key, count] : overlap) {
        const dynamics::InstanceInfo* row = instances.find(key.first);
        if (row == nullptr || row->kind != dynamics::ObjectKind::kRigid) continue;
        const ObjectView& view = views[static_cast<size_t>(key.second)];
        const float fraction =
            static_cast<float>(count) / static_cast<float>(std::max(1, instance_pixels[key.first]));
        if (config.class_must_agree && row->class_id != view.class_id &&
            (fraction < config.any_class_overlap || config.any_class_overlap >= 1.f))
            continue;
        if (fraction >= config.min_overlap) pairs.emplace_back(fraction, key.first, key.second);
    }
    std::sort(pairs.begin(), pairs.end(),
              [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
    std::map<uint16_t, int> view_of_instance;
    for (const auto& [fraction, id, k] : pairs) {
        if (view_of_instance.count(id) || out.instance_of_view[static_cast<size_t>(k)] != 0)
            continue;
        view_of_instance[id] = k;
        out.instance_of_view[static_cast<size_t>(k)] = id;
    }
    std::map<uint16_t, int> claimed;  // unmatched rigid id -> pixels a silhouette took
    std::vector<int> rendered(static_cast<size_t>(n), 0);  // silhouette pixels with a depth

    // Claimed pixels: a matched instance's go to its view; an unclaimed silhouette pixel goes to
    // the nearest view when the frame's depth agrees with the rendered one.
    for (int v = 0; v < size.height; ++v) {
        const uint16_t* l = have_labels ? instances.labels.ptr<uint16_t>(v) : nullptr;
        const uint16_t* s = nearest.ptr<uint16_t>(v);
        const float* nz = nearest_z.ptr<float>(v);
        const float* d = depth_m.ptr<float>(v);
        const float* b = background ? background_depth_m.ptr<float>(v) : nullptr;
        uint16_t* out_l = out.view_labels.ptr<uint16_t>(v);
        // Pixel u of the nearest view's silhouette (s[u] != 0, a measured depth): counted as
        // rendered, and the view's when the frame's depth agrees with its rendering and not
        // with the background's.
        const auto silhouette_takes = [&](int u) {
            ++rendered[s[u] - 1];
            if (!agrees_with_object(d[u], nz[u], config)) return false;
            if (b != nullptr && agrees_with_background(d[u], b[u], config)) return false;
            out_l[u] = s[u];
            ++out.pixels_of_view[s[u] - 1];
            ++out.silhouette_pixels_of_view[s[u] - 1];
            return true;
        };
        for (int u = 0; u < size.width; ++u) {
            const uint16_t id = l ? l[u] : 0;
            if (id != 0) {
                auto it = view_of_instance.find(id);
                if (it != view_of_instance.end()) {
                    // Another map's surface inside this instance (one box over two objects):
                    // that map's pixel.
                    if (config.split_instances_by_silhouette && s[u] != 0 &&
                        s[u] != it->second + 1 && d[u] > 0.f && silhouette_takes(u))
                        continue;
                    out_l[u] = static_cast<uint16_t>(it->second + 1);
                    ++out.pixels_of_view[static_cast<size_t>(it->second)];
                    continue;
                }
                if (!claimable[id]) continue;  // a person or unknown mover keeps its pixels
            }
            if (s[u] == 0 || !(d[u] > 0.f)) continue;
            if (!config.silhouette_when_matched && out.instance_of_view[s[u] - 1] != 0) continue;
            // An unmatched rigid instance here of another class: the silhouette still wins
            // (the detector's other guess of the same surface).
            if (silhouette_takes(u) && id != 0) ++claimed[id];
        }
    }
    // Too little of a missed map's rendering agrees: it claims nothing.
    for (int k = 0; k < n; ++k) {
        const size_t i = static_cast<size_t>(k);
        if (out.instance_of_view[i] != 0 || out.silhouette_pixels_of_view[i] == 0) continue;
        if (static_cast<float>(out.silhouette_pixels_of_view[i]) >=
            config.min_silhouette_fraction * static_cast<float>(rendered[i]))
            continue;
        out.view_labels.setTo(0, out.view_labels == static_cast<uint16_t>(k + 1));
        out.pixels_of_view[i] = out.silhouette_pixels_of_view[i] = 0;
    }
    if (have_labels) {  // what the maps still claim of each unmatched instance
        for (auto& [id, count] : claimed) {
            count = cv::countNonZero((instances.labels == id) & (out.view_labels != 0));
        }
    }
    for (const dynamics::InstanceInfo& row : instances.instances) {
        if (row.kind == dynamics::ObjectKind::kRigid && row.pixels > 0 &&
            !view_of_instance.count(row.id)) {
            out.unmatched_rigid.push_back(row.id);
            out.unmatched_claimed.push_back(claimed[row.id]);
        }
    }
    return out;
}

int add_motion_regions(const cv::Mat& motion_mask, const cv::Mat& object_ids, int min_pixels,
                       dynamics::LabelImage* instances, Association* association) {
    if (motion_mask.empty() || motion_mask.type() != CV_8UC1) return 0;
    if (instances->labels.empty()) instances->labels = cv::Mat::zeros(motion_mask.size(), CV_16UC1);
    if (instances->labels.size() != motion_mask.size()) return 0;
    const bool have_claims = !object_ids.empty() && object_ids.size() == motion_mask.size();
    cv::Mat regions;
    const auto n = static_cast<size_t>(cv::connectedComponents(motion_mask, regions, 8, CV_32S));
    if (n <= 1) return 0;
    // Per region: all its pixels, and those outside every instance and claim (with their box).
    std::vector<int> total(n, 0), free(n, 0);
    std::vector<cv::Rect> boxes(n);
    const auto is_free = [&](int y, int x) {
        return instances->labels.at<uint16_t>(y, x) == 0 &&
               (!have_claims || object_ids.at<uint16_t>(y, x) == 0);
    };
    for (int y = 0; y < regions.rows; ++y) {
        const int* r = regions.ptr<int>(y);
        for (int x = 0; x < regions.cols; ++x) {
            if (r[x] == 0) continue;
            const auto k = static_cast<size_t>(r[x]);
            ++total[k];
            if (!is_free(y, x)) continue;
            ++free[k];
            boxes[k] |= cv::Rect(x, y, 1, 1);
        }
    }
    int next = 1;
    for (const dynamics::InstanceInfo& row : instances->instances) next = std::max(next, row.id + 1);
    std::vector<uint16_t> id_of(n, 0);
    int added = 0;
    for (size_t k = 1; k < n && next <= 65535; ++k) {
        if (free[k] < min_pixels || 2 * free[k] < total[k]) continue;
        id_of[k] = static_cast<uint16_t>(next++);
        ++added;
        dynamics::InstanceInfo row;
        row.id = id_of[k];
        row.class_id = -1;
        row.score = 1.f;
        row.kind = dynamics::ObjectKind::kRigid;
        row.box = cv::Rect2f(boxes[k]);
        row.pixels = free[k];
        instances->instances.push_back(row);
        association->unmatched_rigid.push_back(row.id);
        association->unmatched_claimed.push_back(0);
    }
    if (added == 0) return 0;
    for (int y = 0; y < regions.rows; ++y) {
        const int* r = regions.ptr<int>(y);
        uint16_t* l = instances->labels.ptr<uint16_t>(y);
        for (int x = 0; x < regions.cols; ++x) {
            const uint16_t id = id_of[static_cast<size_t>(r[x])];
            if (id != 0 && is_free(y, x)) l[x] = id;
        }
    }
    return added;
}

}  // namespace df::objects
