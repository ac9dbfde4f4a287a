#include "boxes/image_files.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "draw/pictures.hpp"

namespace df::boxes {
Result<ImageDetections> detect_image_file(BoxSource& source, const std::string& file,
                                          const std::string& out_dir) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
        return error(StatusCode::kNotFound, file + ": no such picture file");
    }
    cv::Mat bgr;
    try {
        bgr = cv::imread(file, cv::IMREAD_COLOR);
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, file + ": cannot be read as a picture: " + e.what());
    }
    if (bgr.empty()) {
        return error(StatusCode::kIoError,
                     file +
                         ": not a picture OpenCV can read (corrupt, truncated or an "
                         "unsupported format)");
    }
    ImageDetections result;
    result.file = file;
    result.width = bgr.cols;
    result.height = bgr.rows;
    io::RgbdImage image;
    cv::cvtColor(bgr, image.rgb, cv::COLOR_BGR2RGB);  // sources take R,G,B like the frames
    const auto start = std::chrono::steady_clock::now();
    auto boxes = source.detect(image, 0);
    result.detect_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!boxes) return Status(boxes.status().code(), file + ": " + boxes.status().message());
    result.detections = std::move(*boxes);
    if (out_dir.empty()) return result;

    std::filesystem::create_directories(out_dir, ec);
    const std::string out = (std::filesystem::path(out_dir) /
                             (std::filesystem::path(file).stem().string() + "_detections.jpg"))
                                .string();
    draw::draw_detections(result.detections, /*bgr=*/true, &bgr);
    bool written = false;
    try {
        written = cv::imwrite(out, bgr);
    } catch (const cv::Exception&) {
        written = false;
    }
    if (!written) return error(StatusCode::kIoError, out + ": cannot write the picture");
    result.written = out;
    return result;
}

std::string describe(const ImageDetections& r) {
    char line[256];
    std::snprintf(line, sizeof(line), "%s: %dx%d, %zu detection%s in %.0f ms\n", r.file.c_str(),
                  r.width, r.height, r.detections.size(), r.detections.size() == 1 ? "" : "s",
                  r.detect_ms);
    std::string text = line;
    for (const detect::Detection& d : r.detections) {
        std::snprintf(line, sizeof(line), "  %-14s %.2f  x %4d y %4d w %4d h %4d\n",
                      d.class_name.c_str(), d.score, cvRound(d.box.x), cvRound(d.box.y),
                      cvRound(d.box.width), cvRound(d.box.height));
        text += line;
    }
    if (!r.written.empty()) text += "  wrote " + r.written + "\n";
    return text;
}

}  // namespace df::boxes
