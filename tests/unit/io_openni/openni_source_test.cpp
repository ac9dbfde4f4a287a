// OpenNiSource reading the DfVirtualCamera driver: a written sequence must come back unchanged
// (colour bytes, depth converted to mm, stamps, intrinsics), and failures must say why.
#include "io/openni/openni_source.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

namespace df::io {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 10;
constexpr int kWidth = 640, kHeight = 480;
constexpr double kUnitsPerM = 5000.0;
constexpr int64_t kFirstStampUs = 1'305'031'102'175'304;  // TUM-like epoch stamp
constexpr int64_t kPeriodUs = 33'333;

struct WrittenFrame {
    cv::Mat rgb;       // R,G,B
    cv::Mat depth_mm;  // what the camera must deliver
    int64_t rgb_stamp_us, depth_stamp_us;
};

std::string seconds_text(int64_t us) {
    char text[64];
    std::snprintf(text, sizeof text, "%lld.%06lld", static_cast<long long>(us / 1'000'000),
                  static_cast<long long>(us % 1'000'000));
    return text;
}

// What the camera must deliver: round(raw * 1000 / units_per_m) millimetres.
cv::Mat depth_mm(const cv::Mat& raw, double units_per_m) {
    cv::Mat mm(raw.size(), CV_16UC1);
    for (int y = 0; y < raw.rows; ++y) {
        for (int x = 0; x < raw.cols; ++x) {
            mm.at<uint16_t>(y, x) =
                static_cast<uint16_t>(std::lround(raw.at<uint16_t>(y, x) * 1000.0 / units_per_m));
        }
    }
    return mm;
}

// Writes a TUM-like folder (associations.txt, rgb/*.png, depth/*.png at 5000 units/m).
std::vector<WrittenFrame> write_sequence(const fs::path& dir) {
    fs::create_directories(dir / "rgb");
    fs::create_directories(dir / "depth");
    std::ofstream list(dir / "associations.txt");
    list << "# t_rgb rgb_path t_depth depth_path\n";
    std::vector<WrittenFrame> frames;
    cv::RNG rng(12345);
    for (int i = 0; i < kFrames; ++i) {
        cv::Mat bgr(kHeight, kWidth, CV_8UC3);
        rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
        cv::Mat raw(kHeight, kWidth, CV_16UC1);
        rng.fill(raw, cv::RNG::UNIFORM, 0, 50000);
        raw.setTo(0, raw < 4000);  // some invalid pixels
        const std::string name = std::to_string(i) + ".png";
        EXPECT_TRUE(cv::imwrite((dir / "rgb" / name).string(), bgr));
        EXPECT_TRUE(cv::imwrite((dir / "depth" / name).string(), raw));

        WrittenFrame f;
        cv::cvtColor(bgr, f.rgb, cv::COLOR_BGR2RGB);
        f.depth_mm = depth_mm(raw, kUnitsPerM);
        f.depth_stamp_us = kFirstStampUs + i * kPeriodUs;
        f.rgb_stamp_us = f.depth_stamp_us + 4'000;  // colour 4 ms after depth, as in TUM
        list << seconds_text(f.rgb_stamp_us) << " rgb/" << name << " "
             << seconds_text(f.depth_stamp_us) << " depth/" << name << "\n";
        frames.push_back(std::move(f));
    }
    return frames;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
    return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

class VirtualCameraTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        char pattern[] = "/tmp/df_openni_test_XXXXXX";
        ASSERT_NE(mkdtemp(pattern), nullptr);
        root_ = new fs::path(pattern);
        frames_ = new std::vector<WrittenFrame>(write_sequence(*root_ / "seq"));
        fs::create_directories(*root_ / "empty");
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete frames_;
        delete root_;
    }
    void SetUp() override {
        for (const char* name :
             {"DF_VIRTUAL_CAMERA_FOLDER", "DF_VIRTUAL_CAMERA_LOCKSTEP", "DF_VIRTUAL_CAMERA_LOOP",
              "DF_VIRTUAL_CAMERA_FX", "DF_VIRTUAL_CAMERA_FY", "DF_VIRTUAL_CAMERA_DEPTH_SCALE"}) {
            unsetenv(name);
        }
    }
    static std::string folder() { return (*root_ / "seq").string(); }
    static std::string uri() { return "df-virtual://" + folder(); }
    static OpenNiConfig config() {
        OpenNiConfig c;
        c.uri = uri();
        return c;
    }
    static const WrittenFrame& written(size_t i) { return (*frames_)[i]; }

    static fs::path* root_;
    static std::vector<WrittenFrame>* frames_;
};
fs::path* VirtualCameraTest::root_ = nullptr;
std::vector<WrittenFrame>* VirtualCameraTest::frames_ = nullptr;

TEST_F(VirtualCameraTest, ListsTheFolderNamedInTheEnvironment) {
    setenv("DF_VIRTUAL_CAMERA_FOLDER", folder().c_str(), 1);
    auto devices = OpenNiSource::list_devices();
    ASSERT_TRUE(devices.is_ok()) << devices.status().to_string();
    bool found = false;
    for (const auto& d : devices.value())
        found = found || (d.uri == uri() && d.vendor == "DetectFusion");
    EXPECT_TRUE(found) << "the virtual device is missing: is the test running with "
                          "LD_LIBRARY_PATH=<build>/openni2 (ctest sets it)?";
}

TEST_F(VirtualCameraTest, LockstepDeliversEveryFrameUnchanged) {
    setenv("DF_VIRTUAL_CAMERA_LOCKSTEP", "1", 1);
    auto source = OpenNiSource::open(config());
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    EXPECT_NEAR(source.value()->intrinsics().fx, 535.4, 0.5);
    EXPECT_NEAR(source.value()->intrinsics().fy, 539.2, 0.5);
    EXPECT_NE(source.value()->describe().find(uri()), std::string::npos);
    for (int i = 0; i < kFrames; ++i) {
        FrameRead read = source.value()->next();
        ASSERT_EQ(read.kind, FrameRead::Kind::kFrame) << "frame " << i << ": " << read.error;
        const RgbdImage& image = read.image;
        EXPECT_EQ(image.index, static_cast<uint64_t>(i));
        EXPECT_TRUE(same(image.rgb, written(i).rgb)) << "colour of frame " << i;
        EXPECT_TRUE(same(image.depth, written(i).depth_mm)) << "depth of frame " << i;
        EXPECT_EQ(image.depth_units_per_m, 1000.0);
        EXPECT_EQ(image.sensor_ns, written(i).depth_stamp_us * 1000);
        EXPECT_NEAR(image.intrinsics.fx, 535.4, 0.5);
        EXPECT_NEAR(image.intrinsics.fy, 539.2, 0.5);
        EXPECT_DOUBLE_EQ(image.intrinsics.cx, kWidth / 2.0);
        EXPECT_DOUBLE_EQ(image.intrinsics.cy, kHeight / 2.0);
    }
    EXPECT_EQ(source.value()->next().kind, FrameRead::Kind::kEnd);
}

TEST_F(VirtualCameraTest, ScaleAndFocalLengthComeFromTheEnvironment) {
    setenv("DF_VIRTUAL_CAMERA_LOCKSTEP", "1", 1);
    setenv("DF_VIRTUAL_CAMERA_FX", "600", 1);
    setenv("DF_VIRTUAL_CAMERA_FY", "610.5", 1);
    setenv("DF_VIRTUAL_CAMERA_DEPTH_SCALE", "10000", 1);  // pretend 0.1 mm units
    auto source = OpenNiSource::open(config());
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    EXPECT_NEAR(source.value()->intrinsics().fx, 600.0, 0.5);
    EXPECT_NEAR(source.value()->intrinsics().fy, 610.5, 0.5);
    FrameRead read = source.value()->next();
    ASSERT_EQ(read.kind, FrameRead::Kind::kFrame) << read.error;
    // written(0).depth_mm holds round(raw / 5); at 10000 units/m the camera gives round(raw / 10).
    const cv::Mat raw = cv::imread((*root_ / "seq/depth/0.png").string(), cv::IMREAD_ANYDEPTH);
    ASSERT_FALSE(raw.empty());
    EXPECT_TRUE(same(read.image.depth, depth_mm(raw, 10000.0)));
}

TEST_F(VirtualCameraTest, LoopStartsOverWithIncreasingStamps) {
    setenv("DF_VIRTUAL_CAMERA_LOCKSTEP", "1", 1);
    setenv("DF_VIRTUAL_CAMERA_LOOP", "1", 1);
    auto source = OpenNiSource::open(config());
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    int64_t last_ns = 0;
    for (int i = 0; i < 2 * kFrames + 5; ++i) {
        FrameRead read = source.value()->next();
        ASSERT_EQ(read.kind, FrameRead::Kind::kFrame) << "frame " << i << ": " << read.error;
        EXPECT_TRUE(same(read.image.rgb, written(i % kFrames).rgb)) << "colour of frame " << i;
        EXPECT_GT(read.image.sensor_ns, last_ns) << "frame " << i;
        last_ns = read.image.sensor_ns;
    }
}

TEST_F(VirtualCameraTest, TimedPlaybackDeliversTrueFramesInOrderThenEnds) {
    // At the sequence rate a slow reader may lose frames, as with a camera: check what arrives.
    auto source = OpenNiSource::open(config());
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    int received = 0;
    int64_t last_ns = 0;
    for (;;) {
        FrameRead read = source.value()->next();
        if (read.kind == FrameRead::Kind::kEnd) break;
        ASSERT_EQ(read.kind, FrameRead::Kind::kFrame) << read.error;
        const int64_t k = (read.image.sensor_ns / 1000 - kFirstStampUs) / kPeriodUs;
        ASSERT_GE(k, 0);
        ASSERT_LT(k, kFrames);
        EXPECT_EQ(read.image.sensor_ns, written(k).depth_stamp_us * 1000);
        EXPECT_TRUE(same(read.image.rgb, written(k).rgb)) << "colour of frame " << k;
        EXPECT_TRUE(same(read.image.depth, written(k).depth_mm)) << "depth of frame " << k;
        EXPECT_GT(read.image.sensor_ns, last_ns);
        last_ns = read.image.sensor_ns;
        ++received;
        ASSERT_LE(received, kFrames);
    }
    EXPECT_GT(received, 0);
}

TEST_F(VirtualCameraTest, GapLongerThanTheTimeoutIsABadFrameThenPlayGoesOn) {
    // Four small frames at 30 Hz with a 1 s hole before the last one.
    const fs::path dir = *root_ / "gap";
    fs::create_directories(dir);
    std::ofstream list(dir / "associations.txt");
    const int64_t stamps_us[] = {0, 33'333, 66'667, 1'066'667};
    for (int i = 0; i < 4; ++i) {
        const std::string name = std::to_string(i) + ".png";
        ASSERT_TRUE(cv::imwrite((dir / ("c" + name)).string(),
                                cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(i * 10))));
        ASSERT_TRUE(cv::imwrite((dir / ("d" + name)).string(), cv::Mat(48, 64, CV_16UC1, 5000)));
        list << seconds_text(stamps_us[i]) << " c" << name << " " << seconds_text(stamps_us[i])
             << " d" << name << "\n";
    }
    list.close();
    OpenNiConfig c;
    c.uri = "df-virtual://" + dir.string();
    c.width = 64;
    c.height = 48;
    c.timeout_ms = 300;
    auto source = OpenNiSource::open(c);
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    // What a reader sees: colour value per frame (0, 10, 20, 30), -1 per timeout. At the
    // sequence rate a frame may be lost under load, so check the shape, not every frame.
    std::vector<int> seen;
    for (FrameRead read = source.value()->next(); read.kind != FrameRead::Kind::kEnd;
         read = source.value()->next()) {
        if (read.kind == FrameRead::Kind::kBadFrame) {
            EXPECT_NE(read.error.find("within 300 ms"), std::string::npos) << read.error;
            seen.push_back(-1);
        } else {
            EXPECT_EQ(read.image.depth.at<uint16_t>(0, 0), 1000);  // 5000 units = 1 m
            seen.push_back(read.image.rgb.at<cv::Vec3b>(0, 0)[0]);
        }
        ASSERT_LT(seen.size(), 12u);
    }
    ASSERT_GE(seen.size(), 2u);
    EXPECT_EQ(seen.back(), 30) << "the frame after the hole comes last";
    EXPECT_EQ(seen[seen.size() - 2], -1) << "the hole is reported as a timeout";
}

TEST_F(VirtualCameraTest, UnknownUriErrorListsTheDevicesFound) {
    setenv("DF_VIRTUAL_CAMERA_FOLDER", folder().c_str(), 1);
    OpenNiConfig c;
    c.uri = "no-such-camera";
    auto source = OpenNiSource::open(c);
    ASSERT_FALSE(source.is_ok());
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    const std::string& message = source.status().message();
    EXPECT_NE(message.find("no-such-camera"), std::string::npos) << message;
    EXPECT_NE(message.find("Devices found: '" + uri() + "'"), std::string::npos) << message;
}

TEST_F(VirtualCameraTest, FolderWithoutAssociationsIsAnError) {
    OpenNiConfig c;
    c.uri = "df-virtual://" + (*root_ / "empty").string();
    auto source = OpenNiSource::open(c);
    ASSERT_FALSE(source.is_ok());
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    EXPECT_NE(source.status().message().find((*root_ / "empty/associations.txt").string()),
              std::string::npos)
        << source.status().message();
}

TEST_F(VirtualCameraTest, UnofferedModeErrorListsTheModes) {
    setenv("DF_VIRTUAL_CAMERA_LOCKSTEP", "1", 1);
    OpenNiConfig c = config();
    c.width = 320;
    c.height = 240;
    auto source = OpenNiSource::open(c);
    ASSERT_FALSE(source.is_ok());
    EXPECT_EQ(source.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(source.status().message().find("offers: 640x480@30 RGB888"), std::string::npos)
        << source.status().message();
}

}  // namespace
}  // namespace df::io
