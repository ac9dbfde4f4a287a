#include "dynamics/instance_propagation.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace df::dynamics {

std::string validate(const PropagationConfig& c) { return params::check(c); }

LabelImage InstancePropagation::carry(const cv::Mat& depth_m, const cv::Mat& geometric,
                                      int geometric_count,
                                      const Eigen::Isometry3f& current_T_previous,
                                      const PinholeCamera& camera,
                                      const PropagationConfig& config) const {
    LabelImage out;
    if (!config.enabled || stored_.empty() || depth_m.size() != depth_.size()) return out;
    const bool segments = !geometric.empty() && geometric.size() == depth_m.size();
    // Which stored rows may still be carried, by label value.
    std::vector<int> row_of(65536, -1);
    std::vector<int> rows;
    for (size_t i = 0; i < stored_.instances.size(); ++i) {
        if (stored_.instances[i].age + 1 > config.max_age_frames) continue;
        row_of[stored_.instances[i].id] = static_cast<int>(rows.size());
        rows.push_back(static_cast<int>(i));
    }
    out.labels = cv::Mat::zeros(depth_m.size(), CV_16UC1);
    if (rows.empty()) {
        out.labels.release();
        return out;
    }
    // Each current pixel looked up in the stored frame (nearest pixel): the stored label there
    // is its vote for its segment, and the pixel keeps it where the depths agree (the same
    // surface, not one that moved away or was uncovered; a segment may hold more than the
    // instance, as a car and the floor it stands on).
    const Eigen::Isometry3f previous_T_current = (current_T_previous * last_T_stored_).inverse();
    const Eigen::Matrix3f r = previous_T_current.linear();
    const Eigen::Vector3f t = previous_T_current.translation();
    const size_t n = rows.size();
    const int count = segments ? geometric_count : 0;
    std::vector<int> votes((static_cast<size_t>(count) + 1) * n, 0);
    std::vector<int> segment_size(static_cast<size_t>(count) + 1, 0);
    for (int y = 0; y < depth_m.rows; ++y) {
        const float* z = depth_m.ptr<float>(y);
        const int32_t* g = segments ? geometric.ptr<int32_t>(y) : nullptr;
        uint16_t* o = out.labels.ptr<uint16_t>(y);
        for (int x = 0; x < depth_m.cols; ++x) {
            const int s = g && g[x] > 0 && g[x] <= count ? g[x] : 0;
            if (s > 0) ++segment_size[s];
            if (!(z[x] > 0.f)) continue;
            const Eigen::Vector3f p((x - camera.cx) * z[x] / camera.fx,
                                    (y - camera.cy) * z[x] / camera.fy, z[x]);
            const Eigen::Vector3f q = r * p + t;
            if (!(q.z() > 0.f)) continue;
            const float pu = camera.fx * q.x() / q.z() + camera.cx;
            const float pv = camera.fy * q.y() / q.z() + camera.cy;
            if (!(pu > -0.5f && pv > -0.5f && pu < depth_.cols - 0.5f && pv < depth_.rows - 0.5f))
                continue;
            const int u = static_cast<int>(std::lround(pu)), v = static_cast<int>(std::lround(pv));
            const uint16_t label = stored_.labels.at<uint16_t>(v, u);
            if (label == 0 || row_of[label] < 0) continue;
            if (s > 0) ++votes[static_cast<size_t>(s) * n + static_cast<size_t>(row_of[label])];
            const float old = depth_.at<float>(v, u);
            const float tolerance =
                config.depth_tolerance_m + config.depth_tolerance_per_m2 * q.z() * q.z();
            if (old > 0.f && std::fabs(q.z() - old) <= tolerance) o[x] = label;
        }
    }
    // Each segment to the carried instance that covers enough of it.
    std::vector<uint16_t> segment_label(static_cast<size_t>(count) + 1, 0);
    for (int s = 1; s <= count; ++s) {
        int best = -1, most = 0;
        for (size_t k = 0; k < n; ++k) {
            const int v = votes[static_cast<size_t>(s) * n + k];
            if (v > most) most = v, best = static_cast<int>(k);
        }
        if (best >= 0 && most >= config.min_segment_overlap * segment_size[s])
            segment_label[s] = stored_.instances[rows[best]].id;
    }
    // The final labels, with each instance's pixel count and bounding box in the same pass.
    std::vector<int> pixels(n, 0);
    std::vector<cv::Rect> boxes(n);
    for (int y = 0; y < depth_m.rows; ++y) {
        const int32_t* g = segments ? geometric.ptr<int32_t>(y) : nullptr;
        uint16_t* o = out.labels.ptr<uint16_t>(y);
        for (int x = 0; x < depth_m.cols; ++x) {
            if (g && g[x] > 0 && g[x] <= count && segment_label[g[x]] != 0)
                o[x] = segment_label[g[x]];
            if (o[x] == 0) continue;
            const int k = row_of[o[x]];
            boxes[k] = pixels[k]++ == 0 ? cv::Rect(x, y, 1, 1) : boxes[k] | cv::Rect(x, y, 1, 1);
        }
    }
    for (size_t k = 0; k < n; ++k) {
        if (pixels[k] == 0) continue;
        InstanceInfo row = stored_.instances[rows[k]];
        ++row.age;
        row.pixels = pixels[k];
        row.box = cv::Rect2f(static_cast<float>(boxes[k].x), static_cast<float>(boxes[k].y),
                             static_cast<float>(boxes[k].width), static_cast<float>(boxes[k].height));
        out.instances.push_back(row);
    }
    if (out.instances.empty()) out.labels.release();
    return out;
}

void InstancePropagation::store(const LabelImage& instances, const cv::Mat& depth_m,
                                const Eigen::Isometry3f& last_T_stored) {
    if (instances.empty() || instances.instances.empty()) {
        clear();
        return;
    }
    // Only rows with pixels in the label image can be carried (the rows SlamSystem adds for
    // what object maps claim, or the instance memory recalls, have theirs elsewhere): the
    // others would only make what is held look fresher than it is (freshest_age).
    std::vector<bool> present(65536, false);
    for (int y = 0; y < instances.labels.rows; ++y) {
        const uint16_t* l = instances.labels.ptr<uint16_t>(y);
        for (int x = 0; x < instances.labels.cols; ++x) present[l[x]] = true;
    }
    std::vector<InstanceInfo> rows;
    for (const InstanceInfo& row : instances.instances)
        if (row.id != 0 && present[row.id]) rows.push_back(row);
    if (rows.empty()) {
        clear();
        return;
    }
    stored_.labels = instances.labels.clone();
    stored_.instances = std::move(rows);
    depth_ = depth_m.clone();
    last_T_stored_ = last_T_stored;
}

int InstancePropagation::freshest_age() const {
    int age = -1;
    for (const InstanceInfo& row : stored_.instances)
        if (age < 0 || row.age < age) age = row.age;
    return age;
}

void InstancePropagation::clear() {
    stored_ = LabelImage{};
    depth_.release();
    last_T_stored_ = Eigen::Isometry3f::Identity();
}

}  // namespace df::dynamics
