#include "dynamics/invalid_mask.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace df::dynamics {

std::string validate(const InvalidMaskConfig& c) { return params::check(c); }

namespace {

std::vector<ObjectKind> kinds_of(const InvalidMaskConfig& c) {
    std::vector<ObjectKind> kinds;
    if (c.non_rigid) kinds.push_back(ObjectKind::kNonRigid);
    if (c.rigid) kinds.push_back(ObjectKind::kRigid);
    if (c.unknown) kinds.push_back(ObjectKind::kUnknown);
    return kinds;
}

/// Gives the pixels of each non-rigid instance's box within its depth range the instance's id in
/// `labels` (CV_16UC1) where they have none yet.
void add_depth_gated_boxes(const LabelImage& objects, const cv::Mat& depth_m, float margin_m,
                           cv::Mat& labels) {
    const cv::Rect frame(0, 0, labels.cols, labels.rows);
    for (const InstanceInfo& info : objects.instances) {
        if (info.kind != ObjectKind::kNonRigid || info.box.width <= 0 || info.box.height <= 0)
            continue;
        const cv::Rect box = cv::Rect(cv::Point(int(std::floor(info.box.x)), int(std::floor(info.box.y))),
                                      cv::Point(int(std::ceil(info.box.x + info.box.width)),
                                                int(std::ceil(info.box.y + info.box.height)))) &
                             frame;
        if (box.empty()) continue;
        std::vector<float> depths;
        for (int y = box.y; y < box.y + box.height; ++y) {
            const uint16_t* l = objects.labels.ptr<uint16_t>(y);
            const float* z = depth_m.ptr<float>(y);
            for (int x = box.x; x < box.x + box.width; ++x)
                if (l[x] == info.id && z[x] > 0.f) depths.push_back(z[x]);
        }
        // A detection that no segment explained (pixels 0): the box's foreground, i.e. the
        // nearest tenth of its depths and a person's thickness behind it.
        const bool unsegmented = depths.size() < 20;
        if (unsegmented) {
            depths.clear();
            for (int y = box.y; y < box.y + box.height; ++y) {
                const float* z = depth_m.ptr<float>(y);
                for (int x = box.x; x < box.x + box.width; ++x)
                    if (z[x] > 0.f) depths.push_back(z[x]);
            }
            if (depths.size() < 20) continue;
        }
        const auto at = [&depths](double q) {
            const size_t k = static_cast<size_t>(q * static_cast<double>(depths.size() - 1));
            std::nth_element(depths.begin(), depths.begin() + static_cast<long>(k), depths.end());
            return depths[k];
        };
        constexpr float kPersonThicknessM = 0.4f;
        const float front = at(unsegmented ? 0.10 : 0.05);
        const float lo = front - margin_m;
        const float hi = (unsegmented ? front + kPersonThicknessM : at(0.95)) + margin_m;
        for (int y = box.y; y < box.y + box.height; ++y) {
            const float* z = depth_m.ptr<float>(y);
            uint16_t* l = labels.ptr<uint16_t>(y);
            for (int x = box.x; x < box.x + box.width; ++x)
                if (l[x] == 0 && z[x] > 0.f && z[x] >= lo && z[x] <= hi) l[x] = info.id;
        }
    }
}

}  // namespace

cv::Mat instance_labels(const FrameSegments& segments, const cv::Mat& depth_m, cv::Size size,
                        const InvalidMaskConfig& c) {
    cv::Mat labels = cv::Mat::zeros(size, CV_16UC1);
    const bool have_labels =
        !segments.objects.labels.empty() && segments.objects.labels.size() == size;
    if (!have_labels) return labels;
    segments.objects.labels.copyTo(labels, mask_of(segments.objects, kinds_of(c), size));
    if (c.non_rigid && c.non_rigid_box_depth_m > 0 && !depth_m.empty() && depth_m.size() == size)
        add_depth_gated_boxes(segments.objects, depth_m, c.non_rigid_box_depth_m, labels);
    if (c.instance_dilate_px > 0 && cv::countNonZero(labels) > 0) {
        // Where two instances meet, the larger id wins.
        const int k = 2 * c.instance_dilate_px + 1;
        cv::dilate(labels, labels, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    }
    return labels;
}

cv::Mat instance_mask(const FrameSegments& segments, const cv::Mat& depth_m, cv::Size size,
                      const InvalidMaskConfig& c) {
    cv::Mat mask = instance_labels(segments, depth_m, size, c) != 0;
    return mask;
}

InvalidMask combine(const FrameSegments& segments, const cv::Mat& instance_ids,
                    const cv::Mat& motion, const cv::Mat& residual_m,
                    const InvalidMaskConfig& c) {
    InvalidMask out;
    const cv::Size size = instance_ids.size();
    const cv::Mat instances = instance_ids != 0;
    out.tracking = instances.clone();
    if (!motion.empty()) cv::bitwise_or(out.tracking, motion, out.tracking);

    out.fusion = out.tracking.clone();
    if (!residual_m.empty() && c.fuse_behind_model_m > 0) {
        for (int y = 0; y < size.height; ++y) {
            const float* r = residual_m.ptr<float>(y);
            uint8_t* f = out.fusion.ptr<uint8_t>(y);
            for (int x = 0; x < size.width; ++x)
                if (f[x] && std::isfinite(r[x]) && r[x] > c.fuse_behind_model_m) f[x] = 0;
        }
    }

    // Labels: instance ids where an instance was left out, then the motion regions.
    out.labels.labels = instance_ids.clone();
    int next_id = 1;
    std::vector<uint8_t> kept(65536, 0);
    for (int y = 0; y < size.height; ++y) {
        const uint16_t* l = instance_ids.ptr<uint16_t>(y);
        for (int x = 0; x < size.width; ++x) kept[l[x]] = 1;
    }
    for (const InstanceInfo& i : segments.objects.instances) {
        if (!kept[i.id]) continue;
        out.labels.instances.push_back(i);
        next_id = std::max(next_id, i.id + 1);
    }
    if (!motion.empty() && cv::countNonZero(motion) > 0) {
        cv::Mat only_motion = motion.clone();
        only_motion.setTo(0, instances);
        cv::Mat regions, stats, centroids;
        const int n = cv::connectedComponentsWithStats(only_motion, regions, stats, centroids, 8);
        for (int k = 1; k < n && next_id <= 65535; ++k, ++next_id) {
            InstanceInfo info;
            info.id = static_cast<uint16_t>(next_id);
            info.kind = ObjectKind::kUnknown;
            info.score = 1.f;
            info.box = cv::Rect2f(static_cast<float>(stats.at<int>(k, cv::CC_STAT_LEFT)),
                                  static_cast<float>(stats.at<int>(k, cv::CC_STAT_TOP)),
                                  static_cast<float>(stats.at<int>(k, cv::CC_STAT_WIDTH)),
                                  static_cast<float>(stats.at<int>(k, cv::CC_STAT_HEIGHT)));
            info.pixels = stats.at<int>(k, cv::CC_STAT_AREA);
            out.labels.instances.push_back(info);
            out.labels.labels.setTo(info.id, regions == k);
        }
    }
    // Instances grown by dilation past their labels: the table's pixel counts follow the image.
    std::vector<int> counts(65536, 0);
    for (int y = 0; y < size.height; ++y) {
        const uint16_t* l = out.labels.labels.ptr<uint16_t>(y);
        for (int x = 0; x < size.width; ++x) ++counts[l[x]];
    }
    for (InstanceInfo& i : out.labels.instances) i.pixels = counts[i.id];
    return out;
}

}  // namespace df::dynamics
