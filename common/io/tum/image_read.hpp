#pragma once
/// Internal to df_io_tum: reading one rgb or depth image of a TUM folder, its size checked from
/// the file's header (image_header.hpp) before anything is decoded.
#include <opencv2/core.hpp>
#include <string>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"

namespace df::io::detail {

/// The size an image must have: at most the maximum, exactly width x height when known.
struct SizeRule {
    int max_width = kMaxWidth, max_height = kMaxHeight;
    int width = 0, height = 0;  ///< 0: not known yet
};

/// A colour image as CV_8UC3 R,G,B (grey and BGRA converted), or what was wrong with the file.
Result<cv::Mat> load_rgb(const std::string& path, const SizeRule& size);

/// A depth image as CV_16UC1, or what was wrong with the file.
Result<cv::Mat> load_depth(const std::string& path, const SizeRule& size);

}  // namespace df::io::detail
