#include "dynamics/frame_segments.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <set>

namespace df::dynamics {

const char* to_string(ObjectKind kind) {
    switch (kind) {
        case ObjectKind::kRigid:
            return "rigid";
        case ObjectKind::kNonRigid:
            return "non_rigid";
        case ObjectKind::kUnknown:
            return "unknown";
    }
    return "?";
}

const InstanceInfo* LabelImage::find(uint16_t id) const {
    for (const InstanceInfo& i : instances)
        if (i.id == id) return &i;
    return nullptr;
}

namespace {

std::string size_text(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

}  // namespace

Status check(const FrameSegments& s, cv::Size size, const std::string& where) {
    if (!s.objects.labels.empty()) {
        const cv::Mat& l = s.objects.labels;
        if (l.type() != CV_16UC1 || l.size() != size) {
            return error(StatusCode::kInvalidArgument,
                         where + ": object label image is " + cv::typeToString(l.type()) + " " +
                             size_text(l.size()) + ", the frame " + size_text(size) +
                             " (CV_16UC1 expected)");
        }
        std::set<uint16_t> ids;
        for (const InstanceInfo& i : s.objects.instances) {
            if (i.id == 0 || !ids.insert(i.id).second) {
                return error(StatusCode::kInvalidArgument,
                             where + ": instance table has id " + std::to_string(i.id) +
                                 (i.id == 0 ? " (0 is background)" : " twice"));
            }
        }
        std::vector<uint8_t> known(65536, 0);
        for (uint16_t id : ids) known[id] = 1;
        for (int y = 0; y < l.rows; ++y) {
            const uint16_t* row = l.ptr<uint16_t>(y);
            for (int x = 0; x < l.cols; ++x) {
                if (row[x] != 0 && !known[row[x]]) {
                    return error(StatusCode::kInvalidArgument,
                                 where + ": object label " + std::to_string(row[x]) +
                                     " at pixel (" + std::to_string(x) + ", " +
                                     std::to_string(y) + ") is not in the instance table");
                }
            }
        }
    }
    if (!s.geometric.empty()) {
        const cv::Mat& g = s.geometric;
        if (g.type() != CV_32SC1 || g.size() != size) {
            return error(StatusCode::kInvalidArgument,
                         where + ": geometric label image is " + cv::typeToString(g.type()) + " " +
                             size_text(g.size()) + ", the frame " + size_text(size) +
                             " (CV_32SC1 expected)");
        }
        double lo = 0, hi = 0;
        cv::minMaxLoc(g, &lo, &hi);
        if (lo < 0 || hi > s.geometric_count) {
            return error(StatusCode::kInvalidArgument,
                         where + ": geometric labels span " + std::to_string(int(lo)) + ".." +
                             std::to_string(int(hi)) + ", outside 0.." +
                             std::to_string(s.geometric_count));
        }
    }
    return Status::ok();
}

FrameSegments downscale(const FrameSegments& s, int factor) {
    if (factor <= 1) return s;
    FrameSegments out;
    out.geometric_count = s.geometric_count;
    out.detections_age = s.detections_age;
    const auto half = [factor](const cv::Mat& m, cv::Mat* o) {
        if (m.empty()) return;
        cv::resize(m, *o, cv::Size(m.cols / factor, m.rows / factor), 0, 0, cv::INTER_NEAREST);
    };
    half(s.objects.labels, &out.objects.labels);
    half(s.geometric, &out.geometric);
    const float f = static_cast<float>(factor);
    std::vector<int> counts(65536, 0);
    for (int y = 0; y < out.objects.labels.rows; ++y) {
        const uint16_t* row = out.objects.labels.ptr<uint16_t>(y);
        for (int x = 0; x < out.objects.labels.cols; ++x) ++counts[row[x]];
    }
    for (InstanceInfo i : s.objects.instances) {
        i.box = cv::Rect2f(i.box.x / f, i.box.y / f, i.box.width / f, i.box.height / f);
        i.pixels = counts[i.id];
        out.objects.instances.push_back(i);
    }
    return out;
}

LabelImage from_labels(const cv::Mat& labels, ObjectKind kind) {
    LabelImage out;
    if (labels.empty()) return out;
    if (labels.type() == CV_16UC1) {
        out.labels = labels.clone();
    } else {
        out.labels = cv::Mat::zeros(labels.size(), CV_16UC1);
        out.labels.setTo(1, labels != 0);
    }
    std::vector<int> counts(65536, 0);
    for (int y = 0; y < out.labels.rows; ++y) {
        const uint16_t* row = out.labels.ptr<uint16_t>(y);
        for (int x = 0; x < out.labels.cols; ++x) ++counts[row[x]];
    }
    for (int id = 1; id < 65536; ++id) {
        if (counts[static_cast<size_t>(id)] == 0) continue;
        InstanceInfo i;
        i.id = static_cast<uint16_t>(id);
        i.kind = kind;
        i.score = 1.f;
        i.pixels = counts[static_cast<size_t>(id)];
        out.instances.push_back(i);
    }
    return out;
}

cv::Mat mask_of(const LabelImage& image, const std::vector<ObjectKind>& kinds, cv::Size size) {
    cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
    if (image.labels.empty() || image.labels.size() != size) return mask;
    std::vector<uint8_t> take(65536, 0);
    for (const InstanceInfo& i : image.instances)
        if (std::find(kinds.begin(), kinds.end(), i.kind) != kinds.end()) take[i.id] = 255;
    for (int y = 0; y < size.height; ++y) {
        const uint16_t* l = image.labels.ptr<uint16_t>(y);
        uint8_t* m = mask.ptr<uint8_t>(y);
        for (int x = 0; x < size.width; ++x) m[x] = take[l[x]];
    }
    return mask;
}

}  // namespace df::dynamics
