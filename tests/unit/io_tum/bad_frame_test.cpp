// Every kind of bad image in a TUM folder is reported as kBadFrame naming the file and the list
// line it came from, and the source goes on to deliver the frames after it.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/tum/tum_folder.hpp"
#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::make_frame;
using test::same_pixels;
using test::TempFolder;
using test::write_file;

/// A folder of three good 64x48 frames; each test damages frame 1 (the middle one).
class BadFrameTest : public ::testing::Test {
  protected:
    void SetUp() override {
        for (int i = 0; i < 3; ++i) frames_.push_back(make_frame(1'000'000'000LL * (i + 1), i));
        ASSERT_TRUE(write_tum_folder(tmp_.str(), frames_));
        config_.folder = tmp_.str();
        config_.intrinsics = test::kSmallIntrinsics;
    }

    std::string rgb1() const { return tmp_ / "rgb/2.000000.png"; }
    std::string depth1() const { return tmp_ / "depth/2.000000.png"; }

    /// Reads the folder and checks: frame 0 good, frame 1 bad with a message containing every
    /// one of `parts`, frame 2 good and identical to what was written, then the end.
    void expect_frame_1_bad(const std::vector<std::string>& parts) {
        auto opened = TumFolderSource::open(config_);
        ASSERT_TRUE(opened) << opened.status().to_string();
        TumFolderSource& source = *opened.value();
        ASSERT_EQ(source.size(), 3);

        const FrameRead first = source.next();
        ASSERT_EQ(first.kind, FrameRead::Kind::kFrame) << first.error;

        const FrameRead bad = source.next();
        ASSERT_EQ(bad.kind, FrameRead::Kind::kBadFrame);
        EXPECT_EQ(bad.error.find('\n'), std::string::npos) << bad.error;
        EXPECT_NE(bad.error.find("frame 1"), std::string::npos) << bad.error;
        for (const std::string& part : parts) {
            EXPECT_NE(bad.error.find(part), std::string::npos)
                << "expected '" << part << "' in: " << bad.error;
        }

        const FrameRead after = source.next();
        ASSERT_EQ(after.kind, FrameRead::Kind::kFrame) << after.error;
        EXPECT_EQ(after.image.index, 2u);
        EXPECT_TRUE(same_pixels(after.image.rgb, frames_[2].rgb));
        EXPECT_TRUE(same_pixels(after.image.depth, frames_[2].depth));
        EXPECT_EQ(source.next().kind, FrameRead::Kind::kEnd);
    }

    TempFolder tmp_;
    std::vector<RgbdImage> frames_;
    TumFolderConfig config_;
};

TEST_F(BadFrameTest, MissingRgbPng) {
    std::filesystem::remove(rgb1());
    expect_frame_1_bad({rgb1(), "associations.txt:2", "does not exist"});
}

TEST_F(BadFrameTest, MissingDepthPngNamesTheDepthListLine) {
    std::filesystem::remove(tmp_ / "associations.txt");
    std::filesystem::remove(depth1());
    // depth.txt has two comment lines before the frames.
    expect_frame_1_bad({depth1(), "depth.txt:4", "does not exist"});
}

TEST_F(BadFrameTest, CorruptRgbPng) {
    write_file(rgb1(), "this is not a PNG at all, just some bytes");
    expect_frame_1_bad({rgb1(), "associations.txt:2", "cannot decode"});
}

TEST_F(BadFrameTest, TruncatedDepthPng) {
    std::filesystem::resize_file(depth1(), 100);
    expect_frame_1_bad({depth1(), "cannot decode"});
}

TEST_F(BadFrameTest, EightBitDepth) {
    cv::Mat depth8(48, 64, CV_8UC1, cv::Scalar(7));
    ASSERT_TRUE(cv::imwrite(depth1(), depth8));
    expect_frame_1_bad(
        {depth1(), "expected a 16-bit 1-channel depth image, found 8-bit 1-channel"});
}

TEST_F(BadFrameTest, SixteenBitColour) {
    cv::Mat rgb16(48, 64, CV_16UC3, cv::Scalar(1000, 2000, 3000));
    ASSERT_TRUE(cv::imwrite(rgb1(), rgb16));
    expect_frame_1_bad({rgb1(), "expected an 8-bit colour image, found 16-bit 3-channel"});
}

TEST_F(BadFrameTest, RgbAndDepthSizesDiffer) {
    cv::Mat small(24, 32, CV_16UC1, cv::Scalar(5000));
    ASSERT_TRUE(cv::imwrite(depth1(), small));
    expect_frame_1_bad({depth1(), "image is 32x24, expected 64x48"});
}

TEST_F(BadFrameTest, ImageOfAnotherSizeThanTheFirstFrameIsSkipped) {
    // Both images of frame 1 are 32x24 (consistent with each other) but the sequence is 64x48.
    const RgbdImage small = make_frame(2'000'000'000, 9, 32, 24);
    cv::Mat bgr;
    cv::cvtColor(small.rgb, bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite(rgb1(), bgr));
    ASSERT_TRUE(cv::imwrite(depth1(), small.depth));
    expect_frame_1_bad({rgb1(), "associations.txt:2", "image is 32x24, expected 64x48"});
}

TEST_F(BadFrameTest, ImageOfAnotherSizeThanConfiguredIsSkipped) {
    config_.width = 64;
    config_.height = 48;
    const RgbdImage one = make_frame(2'000'000'000, 9, 1, 1);
    cv::Mat bgr;
    cv::cvtColor(one.rgb, bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite(rgb1(), bgr));
    expect_frame_1_bad({rgb1(), "image is 1x1, expected 64x48"});
}

TEST_F(BadFrameTest, ImageLargerThanMaximum) {
    const RgbdImage big = make_frame(2'000'000'000, 9, 80, 60);
    cv::Mat bgr;
    cv::cvtColor(big.rgb, bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite(rgb1(), bgr));
    ASSERT_TRUE(cv::imwrite(depth1(), big.depth));
    config_.max_width = 64;
    config_.max_height = 48;
    expect_frame_1_bad({rgb1(), "80x60", "larger than the 64x48 maximum"});
}

TEST_F(BadFrameTest, GreyAndFourChannelColourAreConverted) {
    cv::Mat grey(48, 64, CV_8UC1);
    cv::randu(grey, 0, 256);
    ASSERT_TRUE(cv::imwrite(rgb1(), grey));
    cv::Mat bgra(48, 64, CV_8UC4, cv::Scalar(10, 20, 30, 255));
    ASSERT_TRUE(cv::imwrite(tmp_ / "rgb/3.000000.png", bgra));

    auto source = TumFolderSource::open(config_);
    ASSERT_TRUE(source);
    source.value()->next();
    const FrameRead from_grey = source.value()->next();
    ASSERT_EQ(from_grey.kind, FrameRead::Kind::kFrame) << from_grey.error;
    ASSERT_EQ(from_grey.image.rgb.type(), CV_8UC3);
    const cv::Vec3b pixel = from_grey.image.rgb.at<cv::Vec3b>(5, 7);
    EXPECT_EQ(pixel,
              cv::Vec3b(grey.at<uint8_t>(5, 7), grey.at<uint8_t>(5, 7), grey.at<uint8_t>(5, 7)));
    const FrameRead from_bgra = source.value()->next();
    ASSERT_EQ(from_bgra.kind, FrameRead::Kind::kFrame) << from_bgra.error;
    EXPECT_EQ(from_bgra.image.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));  // R,G,B
}

}  // namespace
}  // namespace df::io
