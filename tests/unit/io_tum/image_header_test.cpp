// Image sizes are read from PNG/JPEG headers and checked before any pixel is decoded; the
// intrinsics must fit the image size.
#include "io/tum/image_header.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/tum/tum_folder.hpp"
#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::TempFolder;
using test::contains;
using test::write_file;

std::string big_endian(uint32_t v) {
    return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
            static_cast<char>(v)};
}

/// A 33-byte file that is only a PNG signature and an IHDR chunk claiming width x height.
std::string png_header_only(uint32_t width, uint32_t height) {
    std::string png("\x89PNG\r\n\x1a\n", 8);
    png += big_endian(13) + "IHDR" + big_endian(width) + big_endian(height);
    png += std::string("\x08\x02\x00\x00\x00", 5);  // 8-bit RGB
    png += big_endian(0);                           // CRC (never checked: never decoded)
    return png;
}

/// A JPEG start: SOI, an APP0 segment, then a baseline frame header claiming width x height.
std::string jpeg_header_only(uint16_t width, uint16_t height) {
    std::string jpeg("\xff\xd8", 2);
    jpeg += std::string("\xff\xe0\x00\x10JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00", 18);
    jpeg += std::string("\xff\xc0\x00\x11\x08", 5);
    jpeg += {static_cast<char>(height >> 8), static_cast<char>(height),
             static_cast<char>(width >> 8), static_cast<char>(width)};
    jpeg += std::string("\x03\x01\x22\x00\x02\x11\x01\x03\x11\x01", 10);
    return jpeg;
}

TEST(ImageHeader, ReadsPngAndJpegSizesFromRealFiles) {
    TempFolder tmp;
    cv::Mat image(48, 64, CV_8UC3, cv::Scalar(1, 2, 3));
    ASSERT_TRUE(cv::imwrite(tmp / "a.png", image));
    ASSERT_TRUE(cv::imwrite(tmp / "a.jpg", image));
    cv::Mat depth(30, 40, CV_16UC1, cv::Scalar(1000));
    ASSERT_TRUE(cv::imwrite(tmp / "d.png", depth));
    for (const char* name : {"a.png", "a.jpg"}) {
        auto header = read_image_header(tmp / name);
        ASSERT_TRUE(header) << name << ": " << header.status().message();
        EXPECT_EQ(header->width, 64) << name;
        EXPECT_EQ(header->height, 48) << name;
    }
    auto d = read_image_header(tmp / "d.png");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->width, 40);
    EXPECT_EQ(d->height, 30);
    EXPECT_EQ(d->format, ImageHeader::Format::kPng);
}

TEST(ImageHeader, CraftedHugeHeadersGiveTheirClaimedSize) {
    TempFolder tmp;
    write_file(tmp / "huge.png", png_header_only(16000, 16000));
    write_file(tmp / "huge.jpg", jpeg_header_only(16000, 16000));
    for (const char* name : {"huge.png", "huge.jpg"}) {
        auto header = read_image_header(tmp / name);
        ASSERT_TRUE(header) << name << ": " << header.status().message();
        EXPECT_EQ(header->width, 16000);
        const Status s = check_image_size(*header, 640, 480, 0, 0);
        ASSERT_FALSE(s);
        EXPECT_TRUE(contains(s.message(), "16000x16000, larger than the 640x480 maximum"))
            << s.message();
    }
}

TEST(ImageHeader, GarbageZeroAndTruncatedHeadersAreRefused) {
    TempFolder tmp;
    write_file(tmp / "text.png", "not an image at all");
    write_file(tmp / "zero.png", png_header_only(0, 480));
    write_file(tmp / "absurd.png", png_header_only(0x80000000u, 1));
    write_file(tmp / "cut.png", png_header_only(64, 48).substr(0, 12));
    write_file(tmp / "cut.jpg", jpeg_header_only(64, 48).substr(0, 15));
    for (const char* name : {"text.png", "zero.png", "absurd.png", "cut.png", "cut.jpg"}) {
        auto header = read_image_header(tmp / name);
        EXPECT_FALSE(header) << name << " read as " << header->width << "x" << header->height;
    }
    EXPECT_EQ(read_image_header(tmp / "none.png").status().code(), StatusCode::kNotFound);
}

TEST(ImageHeader, SizeOtherThanExpectedSaysExpectedAndFound) {
    ImageHeader header;
    header.width = 320;
    header.height = 240;
    const Status s = check_image_size(header, 640, 480, 640, 480);
    ASSERT_FALSE(s);
    EXPECT_TRUE(contains(s.message(), "image is 320x240, expected 640x480")) << s.message();
    EXPECT_TRUE(check_image_size(header, 640, 480, 320, 240));
    EXPECT_TRUE(check_image_size(header, 640, 480, 0, 0));
}

class HugeImageInFolder : public ::testing::Test {
  protected:
    void SetUp() override {
        for (int i = 0; i < 3; ++i)
            frames_.push_back(test::make_frame(1'000'000'000LL * (i + 1), i));
        ASSERT_TRUE(write_tum_folder(tmp_.str(), frames_));
        config_.folder = tmp_.str();
        config_.intrinsics = test::kSmallIntrinsics;
    }
    TempFolder tmp_;
    std::vector<RgbdImage> frames_;
    TumFolderConfig config_;
};

TEST_F(HugeImageInFolder, TinyFileWithHugeIhdrIsSkippedUndecodedAndTheRunGoesOn) {
    // 33 bytes claiming 16000x16000: decoding would allocate 768 MB before noticing the file
    // ends; the header check refuses it first ("not decoded", not a decoder's error).
    write_file(tmp_ / "rgb/2.000000.png", png_header_only(16000, 16000));
    auto source = TumFolderSource::open(config_);
    ASSERT_TRUE(source) << source.status().to_string();
    EXPECT_EQ((*source)->next().kind, FrameRead::Kind::kFrame);
    const FrameRead bad = (*source)->next();
    ASSERT_EQ(bad.kind, FrameRead::Kind::kBadFrame);
    EXPECT_TRUE(contains(bad.error, tmp_ / "rgb/2.000000.png")) << bad.error;
    EXPECT_TRUE(contains(bad.error, "associations.txt:2")) << bad.error;
    EXPECT_TRUE(contains(bad.error, "16000x16000, larger than the 640x480 maximum (not decoded)"))
        << bad.error;
    EXPECT_FALSE(contains(bad.error, "cannot decode")) << bad.error;
    const FrameRead after = (*source)->next();
    ASSERT_EQ(after.kind, FrameRead::Kind::kFrame) << after.error;
    EXPECT_TRUE(test::same_pixels(after.image.depth, frames_[2].depth));
}

TEST_F(HugeImageInFolder, FirstFrameHugeIsRefusedToo) {
    write_file(tmp_ / "depth/1.000000.png", png_header_only(16000, 16000));
    auto source = TumFolderSource::open(config_);
    ASSERT_TRUE(source) << source.status().to_string();
    const FrameRead bad = (*source)->next();
    ASSERT_EQ(bad.kind, FrameRead::Kind::kBadFrame);
    EXPECT_TRUE(contains(bad.error, "16000x16000")) << bad.error;
}

TEST(CheckIntrinsics, NonsenseValuesAreRefusedNamingFieldValueAndRange) {
    struct Case {
        Intrinsics k;
        std::string part;
    };
    const std::vector<Case> cases = {
        {{1e-300, 535, 320, 240}, "fx is 1e-300, allowed [32, 12800] for 640x480 images"},
        {{535, -1, 320, 240}, "fy is -1"},
        {{535, std::nan(""), 320, 240}, "fy is nan"},
        {{535, 539, 1e300, 240}, "cx is 1e+300, allowed [0, 640]"},
        {{535, 539, 320, -3}, "cy is -3, allowed [0, 480]"},
        {{1e9, 539, 320, 240}, "fx is 1e+09"},
    };
    for (const Case& c : cases) {
        const Status s = check_intrinsics(c.k, 640, 480, "intrinsics.txt:2");
        ASSERT_FALSE(s) << c.part;
        EXPECT_TRUE(contains(s.message(), "intrinsics.txt:2: " + c.part)) << s.message();
    }
    EXPECT_TRUE(check_intrinsics(intrinsics_preset("fr3").value(), 640, 480, "fr3"));
    EXPECT_TRUE(check_intrinsics(intrinsics_preset("7scenes").value(), 640, 480, "7scenes"));
}

TEST(CheckIntrinsics, PresetOfAnotherImageSizeIsRefusedAtOpen) {
    // fr3 intrinsics are for 640x480; these images are 64x48.
    TempFolder tmp;
    ASSERT_TRUE(write_tum_folder(tmp.str(), {test::make_frame(1'000'000'000, 1)}));
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = intrinsics_preset("fr3").value();
    auto source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_TRUE(contains(source.status().message(), "cx is 320.1, allowed [0, 64]"))
        << source.status().message();
    EXPECT_TRUE(contains(source.status().message(), "rgb/1.000000.png"))
        << source.status().message();
}

}  // namespace
}  // namespace df::io
