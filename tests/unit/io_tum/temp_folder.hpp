#pragma once
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

class TempFolder {
  public:
    TempFolder() {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const std::string name = std::string("df_io_tum_") + (info ? info->name() : "x") + "_" +
                                 std::to_string(::getpid()) + "_" + std::to_string(counter++);
        path_ = std::filesystem::temp_directory_path() / name;
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::string str() const { return path_.string(); }
    std::string operator/(const std::string& relative) const { return (path_ / relative).string(); }

  private:
    std::filesystem::path path_;
};

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
