#include "draw/pictures.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "detect/detector.hpp"

namespace df::draw {

cv::Scalar kind_tint(dynamics::ObjectKind kind) {
    switch (kind) {
        case dynamics::ObjectKind::kNonRigid:
            return {255, 40, 40};
        case dynamics::ObjectKind::kRigid:
            return {40, 90, 255};
        case dynamics::ObjectKind::kUnknown:
            return {255, 220, 0};
    }
    return {255, 255, 255};
}

std::string class_name(int class_id) {
    const auto& names = detect::coco_names();
    return class_id >= 0 && class_id < static_cast<int>(names.size())
               ? names[static_cast<size_t>(class_id)]
               : std::string("object");
}

cv::Vec3b id_colour(int id) {
    // Hues 53 apart (of OpenCV's 180) and three brightnesses: neighbouring ids look different.
    cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar((id * 53) % 180, 230, 255 - (id / 7 % 3) * 60)), rgb;
    cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
    return rgb.at<cv::Vec3b>(0, 0);
}

void draw_detections(const std::vector<detect::Detection>& detections, bool bgr, cv::Mat* image) {
    const int thickness = std::max(1, std::min(image->cols, image->rows) / 300);
    const double scale = std::max(0.4, std::min(image->cols, image->rows) / 900.0);
    // Worst score first, so that the best box's label ends on top.
    for (auto d = detections.rbegin(); d != detections.rend(); ++d) {
        const cv::Vec3b c = id_colour(d->class_id < 0 ? 0 : d->class_id);
        const cv::Scalar colour = bgr ? cv::Scalar(c[2], c[1], c[0]) : cv::Scalar(c[0], c[1], c[2]);
        const cv::Rect box(cv::Point(cvRound(d->box.x), cvRound(d->box.y)),
                           cv::Point(cvRound(d->box.br().x), cvRound(d->box.br().y)));
        cv::rectangle(*image, box, colour, thickness);
        char label[96];
        std::snprintf(label, sizeof(label), "%s %.2f", d->class_name.c_str(), d->score);
        int baseline = 0;
        const cv::Size text =
            cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
        int top = box.y - text.height - baseline - 2;
        if (top < 0) top = std::min(box.y + 1, image->rows - text.height - baseline - 2);
        const int left = std::clamp(box.x, 0, std::max(0, image->cols - text.width));
        cv::rectangle(*image, cv::Rect(left, top, text.width, text.height + baseline + 2), colour,
                      cv::FILLED);
        cv::putText(*image, label, cv::Point(left, top + text.height + 1), cv::FONT_HERSHEY_SIMPLEX,
                    scale, cv::Scalar(0, 0, 0), thickness, cv::LINE_AA);
    }
}

void tint_instances(const dynamics::LabelImage& labels, float box_scale, cv::Mat* rgb) {
    if (labels.empty() || labels.instances.empty()) return;
    cv::Mat l = labels.labels;
    if (l.size() != rgb->size()) cv::resize(l, l, rgb->size(), 0, 0, cv::INTER_NEAREST);
    std::vector<cv::Vec3b> colour(65536, cv::Vec3b(0, 0, 0));
    std::vector<uint8_t> has(65536, 0);
    for (const dynamics::InstanceInfo& i : labels.instances) {
        const cv::Scalar t = kind_tint(i.kind);
        colour[i.id] = cv::Vec3b(uint8_t(t[0]), uint8_t(t[1]), uint8_t(t[2]));
        has[i.id] = 1;
    }
    for (int y = 0; y < rgb->rows; ++y) {
        cv::Vec3b* p = rgb->ptr<cv::Vec3b>(y);
        const uint16_t* id = l.ptr<uint16_t>(y);
        for (int x = 0; x < rgb->cols; ++x) {
            if (!has[id[x]]) continue;
            for (int c = 0; c < 3; ++c) p[x][c] = uint8_t((p[x][c] + colour[id[x]][c]) / 2);
        }
    }
    for (const dynamics::InstanceInfo& i : labels.instances) {
        if (i.box.width <= 0) continue;
        const cv::Rect box(cv::Point(int(i.box.x * box_scale), int(i.box.y * box_scale)),
                           cv::Size(int(i.box.width * box_scale), int(i.box.height * box_scale)));
        cv::rectangle(*rgb, box, kind_tint(i.kind), 2);
        std::string name =
            i.kind == dynamics::ObjectKind::kUnknown ? "unknown mover" : class_name(i.class_id);
        if (i.kind != dynamics::ObjectKind::kUnknown && i.score < 1.f)
            name += " " + std::to_string(int(i.score * 100 + 0.5f)) + "%";
        cv::putText(*rgb, name, box.tl() + cv::Point(2, 14), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                    kind_tint(i.kind), 1, cv::LINE_AA);
    }
}

cv::Mat colour_segments(const cv::Mat& labels, const cv::Mat& rgb) {
    cv::Mat ids;
    labels.convertTo(ids, CV_32S);
    double max_id = 0;
    if (!ids.empty()) cv::minMaxLoc(ids, nullptr, &max_id);
    std::vector<cv::Vec3b> lut(static_cast<size_t>(std::max(0.0, max_id)) + 1);
    for (size_t i = 1; i < lut.size(); ++i) lut[i] = id_colour(static_cast<int>(i));
    cv::Mat out(ids.size(), CV_8UC3, cv::Scalar(0, 0, 0));
    const bool blend = !rgb.empty() && rgb.size() == ids.size() && rgb.type() == CV_8UC3;
    for (int y = 0; y < ids.rows; ++y) {
        const int* id = ids.ptr<int>(y);
        cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
        const cv::Vec3b* under = blend ? rgb.ptr<cv::Vec3b>(y) : nullptr;
        for (int x = 0; x < ids.cols; ++x) {
            if (id[x] <= 0) {
                if (under) o[x] = under[x] / 3;  // darkened: no segment
                continue;
            }
            const cv::Vec3b c = lut[static_cast<size_t>(id[x])];
            o[x] = under ? cv::Vec3b(uint8_t((c[0] + under[x][0]) / 2),
                                     uint8_t((c[1] + under[x][1]) / 2),
                                     uint8_t((c[2] + under[x][2]) / 2))
                         : c;
        }
    }
    return out;
}

}  // namespace df::draw
