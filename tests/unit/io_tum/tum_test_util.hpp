#pragma once
#include "temp_folder.hpp"
/// Test helpers: a temporary folder removed at the end of the test, small synthetic frames,
/// and writing text files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <string>

#include "io/rgbd_image.hpp"

namespace df::io::test {

using df::test::TempFolder;  // tests/support/temp_folder.hpp

/// fr3's intrinsics scaled to make_frame's default 64x48 images (fr3 itself is for 640x480 and
/// is refused for them: its principal point lies outside a 64x48 image).
inline const Intrinsics kSmallIntrinsics{53.54, 53.92, 32.01, 24.76};

/// True when `part` occurs in `text` (error messages that must name a file, line or field).
inline bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

inline void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    ASSERT_TRUE(out.good()) << "cannot write " << path;
}

/// A frame whose pixels depend on `seed`: random colour, depth 0.5..6 m at 5000 units per metre.
inline RgbdImage make_frame(int64_t sensor_ns, uint64_t seed, int width = 64, int height = 48) {
    RgbdImage frame;
    cv::RNG rng(seed + 1);
    frame.rgb.create(height, width, CV_8UC3);
    rng.fill(frame.rgb, cv::RNG::UNIFORM, 0, 256);
    frame.depth.create(height, width, CV_16UC1);
    rng.fill(frame.depth, cv::RNG::UNIFORM, 2500, 30000);
    frame.sensor_ns = sensor_ns;
    return frame;
}

/// True if both images have the same size, type and bytes.
inline bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
    if (a.size() != b.size() || a.type() != b.type()) return false;
    for (int y = 0; y < a.rows; ++y) {
        if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
    }
    return true;
}

}  // namespace df::io::test
