#include "dds/msg_convert.hpp"

#include <chrono>
#include <cstring>

namespace df::dds {

uint64_t wall_ns() {
    return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     std::chrono::system_clock::now().time_since_epoch())
                                     .count());
}

void fill_frame(const io::RgbdImage& image, const df_msg_Header& header, df_msg_RgbdFrame* frame) {
    frame->header = header;
    frame->width = static_cast<uint16_t>(image.rgb.cols);
    frame->height = static_cast<uint16_t>(image.rgb.rows);
    frame->intrinsics.fx = static_cast<float>(image.intrinsics.fx);
    frame->intrinsics.fy = static_cast<float>(image.intrinsics.fy);
    frame->intrinsics.cx = static_cast<float>(image.intrinsics.cx);
    frame->intrinsics.cy = static_cast<float>(image.intrinsics.cy);
    frame->depth_units_per_m = static_cast<float>(image.depth_units_per_m);
    cv::Mat rgb = rgb_view(*frame);
    cv::Mat depth = depth_view(*frame);
    image.rgb.copyTo(rgb);
    image.depth.copyTo(depth);
}

cv::Mat rgb_view(const df_msg_RgbdFrame& frame) {
    return cv::Mat(frame.height, frame.width, CV_8UC3, const_cast<uint8_t*>(frame.rgb));
}

cv::Mat depth_view(const df_msg_RgbdFrame& frame) {
    return cv::Mat(frame.height, frame.width, CV_16UC1, const_cast<uint16_t*>(frame.depth));
}

io::RgbdImage to_image(const df_msg_RgbdFrame& frame) {
    io::RgbdImage image;
    image.rgb = rgb_view(frame).clone();
    image.depth = depth_view(frame).clone();
    image.depth_units_per_m = frame.depth_units_per_m;
    image.intrinsics = {frame.intrinsics.fx, frame.intrinsics.fy, frame.intrinsics.cx,
                        frame.intrinsics.cy};
    image.sensor_ns = static_cast<int64_t>(frame.header.sensor_ns);
    image.index = frame.header.seq;
    return image;
}

}  // namespace df::dds
