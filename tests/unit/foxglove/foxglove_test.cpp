// The CDR bytes of Foxglove messages, checked at offsets worked out by hand from the encoding's
// rules (4-byte header; each value aligned to its size counted after the header; strings with
// their NUL counted; sequences as a count then the elements).
#include <gtest/gtest.h>

#include <cstring>

#include "foxglove/cdr_writer.hpp"
#include "foxglove/messages.hpp"
#include "foxglove/scene.hpp"

namespace df::foxglove {
namespace {

uint32_t u32_at(const Bytes& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}
double f64_at(const Bytes& b, size_t at) {
    double v;
    std::memcpy(&v, b.data() + at, 8);
    return v;
}

TEST(CdrWriter, AlignsEachValueToItsSizeAfterTheHeader) {
    CdrWriter w;
    w.u8(7);
    w.f64(1.5);      // aligned to 8 after the header: at 4 + 8
    w.string("ab");  // length 3 at 20, then 'a' 'b' NUL
    w.u32(9);        // 27 -> aligned to 4 after the header: 28
    const Bytes b = w.take();
    ASSERT_EQ(b.size(), 32u);
    EXPECT_EQ(b[1], 0x01);  // CDR little endian
    EXPECT_EQ(b[4], 7);
    EXPECT_DOUBLE_EQ(f64_at(b, 12), 1.5);
    EXPECT_EQ(u32_at(b, 20), 3u);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(b.data() + 24), 3), std::string("ab\0", 3));
    EXPECT_EQ(u32_at(b, 28), 9u);
}

TEST(FoxgloveMessages, RawImageCarriesThePixelsAfterItsFields) {
    cv::Mat rgb(2, 2, CV_8UC3);
    for (int i = 0; i < 12; ++i) rgb.data[i] = static_cast<uint8_t>(10 + i);
    auto m = raw_image(3'000'000'007, "camera", rgb);
    ASSERT_TRUE(static_cast<bool>(m)) << m.status().message();
    const Bytes& b = *m;
    // time 4..11, frame_id len at 12 ("camera" + NUL: 7) 16..22, width 24, height 28,
    // encoding len at 32 ("rgb8" + NUL: 5) 36..40, step 44, data count 48, pixels 52..63.
    ASSERT_EQ(b.size(), 64u);
    EXPECT_EQ(u32_at(b, 4), 3u);
    EXPECT_EQ(u32_at(b, 8), 7u);
    EXPECT_EQ(u32_at(b, 24), 2u);
    EXPECT_EQ(u32_at(b, 28), 2u);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(b.data() + 36)), "rgb8");
    EXPECT_EQ(u32_at(b, 44), 6u);
    EXPECT_EQ(u32_at(b, 48), 12u);
    EXPECT_EQ(std::memcmp(b.data() + 52, rgb.data, 12), 0);
}

TEST(FoxgloveMessages, RawImageRefusesTypesFoxgloveCannotShow) {
    EXPECT_FALSE(static_cast<bool>(raw_image(0, "camera", cv::Mat(2, 2, CV_32FC3))));
    EXPECT_FALSE(static_cast<bool>(raw_image(0, "camera", cv::Mat())));
}

TEST(FoxgloveMessages, FrameTransformHoldsThePose) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(1, 2, 3);
    pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Bytes b = frame_transform(5, "world", "camera", pose);
    // time 4..11, "world" len at 12 + 6 bytes (16..21), "camera" len at 24 + 7 (28..34),
    // translation at 36 (offset 32 after the header: a multiple of 8), rotation at 60.
    ASSERT_EQ(b.size(), 92u);
    EXPECT_DOUBLE_EQ(f64_at(b, 36), 1);
    EXPECT_DOUBLE_EQ(f64_at(b, 44), 2);
    EXPECT_DOUBLE_EQ(f64_at(b, 52), 3);
    EXPECT_NEAR(f64_at(b, 76), std::sqrt(0.5), 1e-12);  // z
    EXPECT_NEAR(f64_at(b, 84), std::sqrt(0.5), 1e-12);  // w
}

TEST(SceneEncoder, MasksAreTintedOverTheFramesOwnColourEvenWhenTheCallerReusesItsImage) {
    SceneEncoder encoder;  // raw images: the pixels can be compared
    cv::Mat rgb(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));
    io::RgbdImage image;
    image.rgb = rgb;  // a view, as the tap hands over a sample's memory
    ASSERT_FALSE(encoder.frame(7, 1000, image).empty());
    rgb.setTo(cv::Scalar(200, 200, 200));  // the sample's memory, reused by the next one
    dynamics::LabelImage labels;
    labels.labels = cv::Mat::zeros(2, 2, CV_16UC1);
    labels.labels.at<uint16_t>(0, 0) = 1;  // one pixel of a person
    dynamics::InstanceInfo person;
    person.id = 1;
    person.class_id = 0;
    person.kind = dynamics::ObjectKind::kNonRigid;
    labels.instances.push_back(person);
    const auto masks = encoder.instances(7, 1000, labels);
    ASSERT_EQ(masks.size(), 1u);
    const Bytes& b = masks[0].data;
    ASSERT_EQ(b.size(), 64u);  // the RawImage layout of RawImageCarriesThePixelsAfterItsFields
    const uint8_t* px = b.data() + 52;
    // Pixel (0,0): half the frame's colour, half the person tint (255, 40, 40).
    EXPECT_EQ(px[0], (10 + 255) / 2);
    EXPECT_EQ(px[1], (20 + 40) / 2);
    // The others: the frame's own colour, not what the caller wrote afterwards.
    for (int i = 1; i < 4; ++i) {
        EXPECT_EQ(px[3 * i], 10) << "pixel " << i;
        EXPECT_EQ(px[3 * i + 1], 20) << "pixel " << i;
        EXPECT_EQ(px[3 * i + 2], 30) << "pixel " << i;
    }
}

}  // namespace
}  // namespace df::foxglove
