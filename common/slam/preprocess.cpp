#include <opencv2/imgproc.hpp>
#include <sstream>

#include "slam/depth_maps.hpp"
#include "slam/frame.hpp"

namespace df::slam {

std::string validate(const PreprocessConfig& c) {
    if (std::string e = params::check(c); !e.empty()) return e;
    if (!(c.min_depth_m > 0.f && c.max_depth_m > c.min_depth_m)) {
        std::ostringstream msg;
        msg << "need 0 < min_depth_m < max_depth_m, got min_depth_m=" << c.min_depth_m
            << " max_depth_m=" << c.max_depth_m;
        return msg.str();
    }
    return "";
}

namespace {

std::string validate_image(const io::RgbdImage& image, int levels) {
    std::ostringstream msg;
    const std::string where =
        image.depth_path.empty() ? std::string() : " (" + image.depth_path + ")";
    if (image.depth.empty() || image.depth.type() != CV_16UC1) {
        msg << "depth must be a non-empty CV_16UC1 image" << where;
    } else if (image.rgb.type() != CV_8UC3 || image.rgb.size() != image.depth.size()) {
        msg << "rgb must be CV_8UC3 of the depth's size " << image.depth.cols << "x"
            << image.depth.rows << ", got " << image.rgb.cols << "x" << image.rgb.rows << " type "
            << image.rgb.type() << where;
    } else if (!(image.depth_units_per_m > 0.0)) {
        msg << "depth_units_per_m must be > 0, got " << image.depth_units_per_m << where;
    } else if (!(image.intrinsics.fx > 0.0 && image.intrinsics.fy > 0.0)) {
        msg << "focal lengths must be > 0, got fx=" << image.intrinsics.fx
            << " fy=" << image.intrinsics.fy;
    } else if ((image.depth.cols >> (levels - 1)) < 8 || (image.depth.rows >> (levels - 1)) < 8) {
        msg << "image " << image.depth.cols << "x" << image.depth.rows << " too small for "
            << levels << " pyramid levels (coarsest must be at least 8x8)";
    }
    return msg.str();
}

// Vertices, normals and intensity gradients of a level whose depths and intensity are set.
void finish_level(FrameLevel& level, int normal_baseline_px) {
    level.vertex = compute_vertex_map(level.depth_m, level.intrinsics);
    level.smoothed_vertex = compute_vertex_map(level.smoothed_depth_m, level.intrinsics);
    level.normal =
        compute_normal_map(level.smoothed_depth_m, level.intrinsics, normal_baseline_px);
    cv::Sobel(level.intensity, level.grad_x, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(level.intensity, level.grad_y, CV_32F, 0, 1, 3, 1.0 / 8.0);
}

}  // namespace

Result<Frame> preprocess(const io::RgbdImage& image, const PreprocessConfig& config) {
    if (std::string bad = validate(config); !bad.empty()) {
        return error(StatusCode::kInvalidArgument, "PreprocessConfig: " + bad);
    }
    if (std::string bad = validate_image(image, config.pyramid_levels); !bad.empty()) {
        return error(StatusCode::kInvalidArgument,
                     "preprocess frame " + std::to_string(image.index) + ": " + bad);
    }
    Frame frame;
    frame.sensor_ns = image.sensor_ns;
    frame.index = image.index;
    frame.sensor_size = image.depth.size();
    frame.levels.resize(static_cast<size_t>(config.pyramid_levels));

    FrameLevel& base = frame.levels[0];
    base.intrinsics = image.intrinsics;
    base.depth_m = depth_to_metres(image.depth, image.depth_units_per_m, config.min_depth_m,
                                   config.max_depth_m);
    base.smoothed_depth_m =
        bilateral_filter_depth(base.depth_m, config.bilateral_sigma_space_px,
                               config.bilateral_sigma_depth_m, config.bilateral_radius_px);
    base.intensity = rgb_to_intensity(image.rgb);
    finish_level(base, config.normal_baseline_px);

    for (size_t l = 1; l < frame.levels.size(); ++l) {
        const FrameLevel& finer = frame.levels[l - 1];
        FrameLevel& level = frame.levels[l];
        level.intrinsics = scale_intrinsics(image.intrinsics, static_cast<int>(l));
        level.depth_m = downsample_depth(finer.depth_m, config.pyramid_max_depth_diff_m);
        level.smoothed_depth_m =
            downsample_depth(finer.smoothed_depth_m, config.pyramid_max_depth_diff_m);
        cv::pyrDown(finer.intensity, level.intensity, level.depth_m.size());
        finish_level(level, config.normal_baseline_px);
    }
    return frame;
}

Frame crop(const Frame& frame, const cv::Rect& roi, cv::Rect* used) {
    Frame out;
    out.sensor_ns = frame.sensor_ns;
    out.index = frame.index;
    out.sensor_size = frame.sensor_size;
    *used = cv::Rect();
    if (frame.levels.empty()) return out;
    const int align = 1 << (static_cast<int>(frame.levels.size()) - 1);
    const cv::Size size = frame.levels[0].depth_m.size();
    // Outwards to the alignment, then inwards to the frame's last whole aligned block.
    const int x0 = std::max(0, roi.x / align * align);
    const int y0 = std::max(0, roi.y / align * align);
    const int x1 = std::min(size.width / align * align, (roi.br().x + align - 1) / align * align);
    const int y1 = std::min(size.height / align * align, (roi.br().y + align - 1) / align * align);
    if (x1 <= x0 || y1 <= y0) {
        out.levels.resize(frame.levels.size());
        return out;
    }
    *used = cv::Rect(x0, y0, x1 - x0, y1 - y0);
    for (size_t l = 0; l < frame.levels.size(); ++l) {
        const FrameLevel& in = frame.levels[l];
        const int s = 1 << l;
        const cv::Rect r(x0 / s, y0 / s, (x1 - x0) / s, (y1 - y0) / s);
        FrameLevel level;
        level.intrinsics = in.intrinsics;
        level.intrinsics.cx -= r.x;
        level.intrinsics.cy -= r.y;
        const auto view = [&r](const cv::Mat& m) { return m.empty() ? m : m(r); };
        level.depth_m = view(in.depth_m);
        level.smoothed_depth_m = view(in.smoothed_depth_m);
        level.vertex = view(in.vertex);
        level.smoothed_vertex = view(in.smoothed_vertex);
        level.normal = view(in.normal);
        level.intensity = view(in.intensity);
        level.grad_x = view(in.grad_x);
        level.grad_y = view(in.grad_y);
        out.levels.push_back(std::move(level));
    }
    return out;
}

}  // namespace df::slam
