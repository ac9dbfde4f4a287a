#include "mask_outputs.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "draw/pictures.hpp"
#include "eval/plot_canvas.hpp"
#include "io/tum/stamp.hpp"

namespace df::slam_service {
namespace {

cv::Mat upscale(const cv::Mat& labels, cv::Size size) {
    if (labels.empty()) return cv::Mat::zeros(size, CV_16UC1);
    cv::Mat out;
    if (labels.size() == size) {
        out = labels;
    } else {
        cv::resize(labels, out, size, 0, 0, cv::INTER_NEAREST);
    }
    if (out.type() != CV_16UC1) out.convertTo(out, CV_16UC1);
    return out;
}

using eval::write_png;

/// Object map pixels tinted with the object's colour, its id and class at its centre.
void draw_objects(const cv::Mat& object_ids, const std::vector<objects::ObjectReport>& reports,
                  cv::Mat* rgb) {
    if (object_ids.empty()) return;
    const cv::Mat ids = upscale(object_ids, rgb->size());
    for (const objects::ObjectReport& r : reports) {
        const cv::Mat mine = ids == static_cast<uint16_t>(r.id);
        if (cv::countNonZero(mine) == 0) continue;
        const cv::Vec3b c = draw::id_colour(r.id);
        cv::Mat tint(rgb->size(), CV_8UC3, cv::Scalar(c[0], c[1], c[2]));
        cv::Mat blended;
        cv::addWeighted(*rgb, 0.4, tint, 0.6, 0, blended);
        blended.copyTo(*rgb, mine);
        const cv::Rect box = cv::boundingRect(mine);
        cv::rectangle(*rgb, box, cv::Scalar(c[0], c[1], c[2]), 2);
        const std::string text = "#" + std::to_string(r.id) + " " + draw::class_name(r.class_id) +
                                 (r.tracked ? "" : " (not tracked)");
        cv::putText(*rgb, text, box.tl() + cv::Point(2, -4), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                    cv::Scalar(c[0], c[1], c[2]), 1, cv::LINE_AA);
    }
}

cv::Mat overlay(const io::RgbdImage& image, const dynamics::LabelImage& invalid, float scale,
                const slam::FrameReport& report) {
    cv::Mat rgb = image.rgb.clone();  // R,G,B
    draw::tint_instances(invalid, scale, &rgb);
    draw_objects(report.object_ids, report.objects, &rgb);
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    return bgr;
}

}  // namespace

Result<MaskOutputs> MaskOutputs::open(const std::string& dir, bool with_overlay) {
    std::error_code ec;
    for (const char* sub : {"invalid", "motion", "segments", "object_masks", "overlay"}) {
        if (std::string(sub) == "overlay" && !with_overlay) continue;
        std::filesystem::create_directories(dir + "/" + sub, ec);
        if (ec) {
            return error(StatusCode::kIoError,
                         "cannot create " + dir + "/" + sub + ": " + ec.message());
        }
    }
    return MaskOutputs(dir, with_overlay);
}

Status MaskOutputs::write(const io::RgbdImage& image, const dynamics::FrameSegments& segments,
                          const slam::FrameReport& report, int factor) const {
    const cv::Size size = image.depth.size();
    const std::string name = io::stamp_text(report.sensor_ns);
    DF_RETURN_IF_ERROR(
        write_png(dir_ + "/invalid/" + name + ".png", upscale(report.invalid.labels.labels, size)));
    cv::Mat motion = cv::Mat::zeros(size, CV_16UC1);
    if (!report.motion.mask.empty() && cv::countNonZero(report.motion.mask) > 0) {
        cv::Mat regions;
        cv::connectedComponents(report.motion.mask, regions, 8, CV_32S);
        motion = upscale(regions, size);
    }
    DF_RETURN_IF_ERROR(write_png(dir_ + "/motion/" + name + ".png", motion));
    // The instances the frame came with, or those carried into it (at the processing
    // resolution) when its detections were not fresh.
    const cv::Mat& instances =
        report.carried > 0 ? report.instances.labels : segments.objects.labels;
    DF_RETURN_IF_ERROR(write_png(dir_ + "/segments/" + name + ".png", upscale(instances, size)));
    DF_RETURN_IF_ERROR(
        write_png(dir_ + "/object_masks/" + name + ".png", upscale(report.object_ids, size)));
    if (overlay_) {
        DF_RETURN_IF_ERROR(write_png(dir_ + "/overlay/" + name + ".png",
                                     overlay(image, report.invalid.labels, float(factor), report)));
    }
    return Status::ok();
}

}  // namespace df::slam_service
