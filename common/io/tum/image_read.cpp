// Reading rgb and depth images of a TUM folder: sizes checked from the header first, then
// decoded and converted (split from tum_folder.cpp).
#include "io/tum/image_read.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/tum/image_header.hpp"
#include "io/tum/image_text.hpp"

namespace df::io::detail {
namespace fs = std::filesystem;

const char* depth_name(int cv_depth) {
    switch (cv_depth) {
        case CV_8U:
            return "8-bit";
        case CV_8S:
            return "8-bit signed";
        case CV_16U:
            return "16-bit";
        case CV_16S:
            return "16-bit signed";
        case CV_32S:
            return "32-bit integer";
        case CV_32F:
            return "32-bit float";
        case CV_64F:
            return "64-bit float";
        default:
            return "unknown";
    }
}

/// e.g. "8-bit 1-channel".
std::string type_name(const cv::Mat& m) {
    return std::string(depth_name(m.depth())) + " " + std::to_string(m.channels()) + "-channel";
}

std::string size_name(const cv::Mat& m) {
    return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

namespace {

/// Reads an image, turning both a missing file and an undecodable one into a message. The size
/// is checked from the file's header before anything is decoded.
Result<cv::Mat> read_image(const std::string& path, int flags, const SizeRule& size) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        return error(StatusCode::kNotFound,
                     fs::exists(path, ec) ? "is not a file" : "file does not exist");
    }
    auto header = read_image_header(path);
    if (!header) {
        return error(StatusCode::kIoError, "cannot decode image: " + header.status().message());
    }
    DF_RETURN_IF_ERROR(
        check_image_size(*header, size.max_width, size.max_height, size.width, size.height));
    cv::Mat image;
    try {
        image = cv::imread(path, flags);
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, std::string("cannot decode image: ") + e.what());
    }
    if (image.empty()) {
        return error(StatusCode::kIoError,
                     "cannot decode image (corrupt, truncated or not an image file)");
    }
    if (image.cols != header->width || image.rows != header->height) {
        return error(StatusCode::kIoError,
                     "decoded image is " + size_name(image) + " but its header says " +
                         std::to_string(header->width) + "x" + std::to_string(header->height));
    }
    return image;
}

/// Converts what imread returned to CV_8UC3 in R,G,B order, or says why it cannot.
Result<cv::Mat> to_rgb(const cv::Mat& raw) {
    if (raw.depth() != CV_8U) {
        return error(StatusCode::kInvalidArgument,
                     "expected an 8-bit colour image, found " + type_name(raw));
    }
    int code = -1;
    switch (raw.channels()) {
        case 1:
            code = cv::COLOR_GRAY2RGB;
            break;
        case 3:
            code = cv::COLOR_BGR2RGB;
            break;
        case 4:
            code = cv::COLOR_BGRA2RGB;
            break;
        default:
            return error(StatusCode::kInvalidArgument,
                         "expected an 8-bit colour image, found " + type_name(raw));
    }
    cv::Mat rgb;
    cv::cvtColor(raw, rgb, code);
    return rgb;
}

}  // namespace

/// Reads a colour image as CV_8UC3 R,G,B of the allowed size, or says what was wrong.
Result<cv::Mat> load_rgb(const std::string& path, const SizeRule& size) {
    auto raw = read_image(path, cv::IMREAD_UNCHANGED, size);
    if (!raw) return raw.status();
    return to_rgb(*raw);
}

/// Reads a depth image as CV_16UC1 of the allowed size, or says what was wrong.
Result<cv::Mat> load_depth(const std::string& path, const SizeRule& size) {
    auto depth = read_image(path, cv::IMREAD_UNCHANGED, size);
    if (!depth) return depth.status();
    if (depth->type() != CV_16UC1) {
        return error(StatusCode::kInvalidArgument,
                     "expected a 16-bit 1-channel depth image, found " + type_name(*depth));
    }
    return depth;
}

}  // namespace df::io::detail

namespace df::io {

Result<RgbdImage> read_rgbd_files(const std::string& color, const std::string& depth,
                                  const Intrinsics& intrinsics, double depth_units_per_m) {
    RgbdImage image;
    auto d = detail::load_depth(depth, detail::SizeRule{});
    if (!d) return Status(d.status().code(), depth + ": " + d.status().message());
    image.depth = std::move(*d);
    if (!color.empty()) {
        detail::SizeRule same;
        same.width = image.depth.cols;
        same.height = image.depth.rows;
        auto c = detail::load_rgb(color, same);
        if (!c) return Status(c.status().code(), color + ": " + c.status().message());
        image.rgb = std::move(*c);
    } else {
        image.rgb = cv::Mat(image.depth.size(), CV_8UC3, cv::Scalar(128, 128, 128));
    }
    image.intrinsics = intrinsics;
    image.depth_units_per_m = depth_units_per_m;
    image.rgb_path = color;
    image.depth_path = depth;
    return image;
}

}  // namespace df::io
