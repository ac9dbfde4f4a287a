// Writing TUM RGB-D folders (write_tum_folder), split from the reader in tum_folder.cpp.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/tum/image_text.hpp"
#include "io/tum/stamp.hpp"
#include "io/tum/tum_folder.hpp"

namespace df::io {
namespace fs = std::filesystem;

namespace {

using detail::size_name;
using detail::type_name;

Status check_frame_for_writing(const RgbdImage& frame, size_t i) {
    const std::string where = "frame " + std::to_string(i) + ": ";
    if (frame.rgb.empty() || frame.rgb.type() != CV_8UC3) {
        return error(
            StatusCode::kInvalidArgument,
            where + "rgb must be 8-bit 3-channel, found " +
                (frame.rgb.empty() ? std::string("an empty image") : type_name(frame.rgb)));
    }
    if (frame.depth.empty() || frame.depth.type() != CV_16UC1) {
        return error(
            StatusCode::kInvalidArgument,
            where + "depth must be 16-bit 1-channel, found " +
                (frame.depth.empty() ? std::string("an empty image") : type_name(frame.depth)));
    }
    if (frame.rgb.size() != frame.depth.size()) {
        return error(StatusCode::kInvalidArgument, where + "rgb is " + size_name(frame.rgb) +
                                                       " but depth is " + size_name(frame.depth));
    }
    if (frame.sensor_ns < 0) {
        return error(StatusCode::kInvalidArgument,
                     where + "sensor_ns must be >= 0, found " + std::to_string(frame.sensor_ns));
    }
    return Status::ok();
}

Status write_png(const std::string& path, const cv::Mat& image) {
    bool written = false;
    try {
        written = cv::imwrite(path, image);
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, "cannot write " + path + ": " + e.what());
    }
    if (!written) return error(StatusCode::kIoError, "cannot write " + path);
    return Status::ok();
}

Status write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + path);
    return Status::ok();
}

}  // namespace

Status write_tum_folder(const std::string& folder, const std::vector<RgbdImage>& frames) {
    for (size_t i = 0; i < frames.size(); ++i)
        DF_RETURN_IF_ERROR(check_frame_for_writing(frames[i], i));
    // Lists are written in stamp order, as TUM's are, whatever order the frames came in.
    std::vector<size_t> order(frames.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return frames[a].sensor_ns < frames[b].sensor_ns; });
    std::vector<std::string> stamps;
    stamps.reserve(frames.size());
    for (const RgbdImage& frame : frames) stamps.push_back(stamp_text(frame.sensor_ns));
    for (size_t k = 1; k < order.size(); ++k) {
        if (stamps[order[k]] == stamps[order[k - 1]]) {
            return error(StatusCode::kInvalidArgument,
                         "frames " + std::to_string(order[k - 1]) + " and " +
                             std::to_string(order[k]) + " have the same stamp " + stamps[order[k]] +
                             " s (files are named by stamp)");
        }
    }

    const fs::path root(folder);
    std::error_code ec;
    for (const fs::path& dir : {root, root / "rgb", root / "depth"}) {
        fs::create_directories(dir, ec);
        if (ec || !fs::is_directory(dir, ec)) {
            return error(StatusCode::kIoError, "cannot create folder " + dir.string() +
                                                   (ec ? " (" + ec.message() + ")" : ""));
        }
    }

    std::string rgb_list = "# color images\n# timestamp filename\n";
    std::string depth_list = "# depth maps\n# timestamp filename\n";
    std::string associations;
    for (size_t i : order) {
        const std::string rgb_name = "rgb/" + stamps[i] + ".png";
        const std::string depth_name = "depth/" + stamps[i] + ".png";
        cv::Mat bgr;
        cv::cvtColor(frames[i].rgb, bgr, cv::COLOR_RGB2BGR);
        DF_RETURN_IF_ERROR(write_png((root / rgb_name).string(), bgr));
        DF_RETURN_IF_ERROR(write_png((root / depth_name).string(), frames[i].depth));
        rgb_list += stamps[i] + " " + rgb_name + "\n";
        depth_list += stamps[i] + " " + depth_name + "\n";
        associations += stamps[i] + " " + rgb_name + " " + stamps[i] + " " + depth_name + "\n";
    }
    DF_RETURN_IF_ERROR(write_text((root / "rgb.txt").string(), rgb_list));
    DF_RETURN_IF_ERROR(write_text((root / "depth.txt").string(), depth_list));
    DF_RETURN_IF_ERROR(write_text((root / "associations.txt").string(), associations));
    return Status::ok();
}

}  // namespace df::io
