#pragma once
/// Internal to df_io_tum: how images are named in messages ("8-bit 1-channel", "640x480").
#include <opencv2/core.hpp>
#include <string>

namespace df::io::detail {

const char* depth_name(int cv_depth);
/// e.g. "8-bit 1-channel".
std::string type_name(const cv::Mat& m);
/// e.g. "640x480".
std::string size_name(const cv::Mat& m);

}  // namespace df::io::detail
