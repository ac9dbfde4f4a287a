#pragma once
/// Conversions between topic samples and the libraries' OpenCV types.
/// Views alias the sample's memory (valid while the sample is): no copy.
#include <opencv2/core.hpp>

#include "df_msgs.h"
#include "io/rgbd_image.hpp"

namespace df::dds {

/// Wall-clock time now, ns since the Unix epoch (the clock of Header.capture_ns).
uint64_t wall_ns();

/// Fills a frame sample from an image (size must be <= 640x480; checked by the sources).
void fill_frame(const io::RgbdImage& image, const df_msg_Header& header, df_msg_RgbdFrame* frame);

/// CV_8UC3 (RGB) and CV_16UC1 views of a frame sample.
cv::Mat rgb_view(const df_msg_RgbdFrame& frame);
cv::Mat depth_view(const df_msg_RgbdFrame& frame);

/// An owning RgbdImage copied from a frame sample.
io::RgbdImage to_image(const df_msg_RgbdFrame& frame);

}  // namespace df::dds
