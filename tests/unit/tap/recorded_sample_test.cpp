// tap play's boundary: a recorded message is decoded and checked before it may be published; a
// corrupt one is an error naming the file, the message (index, topic, sequence, log time) and
// the field with its value and limit, and a good one decodes to the recorded sample.
#include "recorded_sample.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "dds/cdr.hpp"

namespace df::tap {
namespace {

std::unique_ptr<df_msg_RgbdFrame> small_frame() {
    auto f = std::make_unique<df_msg_RgbdFrame>();
    *f = {};
    f->header.seq = 9;
    f->header.epoch = 1764599999000000000ULL;
    f->width = 4;
    f->height = 2;
    f->intrinsics = {500.f, 500.f, 2.f, 1.f};
    f->depth_units_per_m = 5000;
    f->depth[7] = 1234;
    f->rgb[23] = 200;
    return f;
}

const dds::TypeInfo& type_of(const char* name) {
    const dds::TypeInfo* t = dds::find_type(name);
    EXPECT_NE(t, nullptr) << name;
    return *t;
}

/// decode_recorded() of `bytes` as message 5 of run.mcap; the sample lands in `out`.
template <typename T>
Status decode(const char* type, const std::vector<uint8_t>& bytes, T& out) {
    mcap::Message m;
    m.channel_id = 1;
    m.sequence = 9;
    m.log_time_ns = 1764600000000000123ULL;
    m.data = bytes.data();
    m.size = bytes.size();
    std::memset(&out, 0, sizeof out);
    const dds::TypeInfo& t = type_of(type);
    const Status s = decode_recorded(t, m, RecordRef{"/tmp/x/run.mcap", 5, "df/frames"}, &out);
    dds_sample_free(&out, t.descriptor, DDS_FREE_CONTENTS);
    return s;
}

constexpr const char* kWhere =
    "/tmp/x/run.mcap: message 5 (topic 'df/frames', sequence 9, log time 1764600000000000123 ns)";

TEST(RecordedSample, AGoodFrameDecodesToTheRecordedSample) {
    const auto f = small_frame();
    const auto bytes = dds::to_cdr(&df_msg_RgbdFrame_desc, f.get());
    auto out = std::make_unique<df_msg_RgbdFrame>();
    ASSERT_TRUE(decode("df::msg::RgbdFrame", bytes, *out).is_ok());
    EXPECT_EQ(out->header.seq, 9U);
    EXPECT_EQ(out->header.epoch, 1764599999000000000ULL);
    EXPECT_EQ(out->width, 4);
    EXPECT_EQ(out->depth[7], 1234);
    EXPECT_EQ(out->rgb[23], 200);
}

TEST(RecordedSample, AFrameWiderThanItsBuffersIsRefusedNamingFileMessageAndField) {
    auto f = small_frame();
    f->width = 1000;  // a consumer would read rows past the 640x480 buffers
    const auto bytes = dds::to_cdr(&df_msg_RgbdFrame_desc, f.get());
    auto out = std::make_unique<df_msg_RgbdFrame>();
    const Status s = decode("df::msg::RgbdFrame", bytes, *out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(s.message(), std::string(kWhere) + ": RgbdFrame.width 1000 > MAX_WIDTH 640");
}

TEST(RecordedSample, APoseWithNaNIsRefusedNamingTheField) {
    df_msg_CameraPose p{};
    p.world_T_camera.qw = 1;
    p.world_T_camera.ty = std::nan("");
    const auto bytes = dds::to_cdr(&df_msg_CameraPose_desc, &p);
    df_msg_CameraPose out{};
    const Status s = decode("df::msg::CameraPose", bytes, out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find(kWhere), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("CameraPose.world_T_camera.ty nan not in"), std::string::npos)
        << s.message();
}

TEST(RecordedSample, TooManyDetectionsAreRefused) {
    auto d = std::make_unique<df_msg_Detections>();
    *d = {};
    d->count = 5000;
    const auto bytes = dds::to_cdr(&df_msg_Detections_desc, d.get());
    auto out = std::make_unique<df_msg_Detections>();
    const Status s = decode("df::msg::Detections", bytes, *out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("Detections.count 5000 > MAX_DETECTIONS 128"), std::string::npos)
        << s.message();
}

TEST(RecordedSample, TruncatedBytesAreRefusedNamingFileAndMessage) {
    const auto f = small_frame();
    auto bytes = dds::to_cdr(&df_msg_RgbdFrame_desc, f.get());
    bytes.resize(bytes.size() / 2);
    auto out = std::make_unique<df_msg_RgbdFrame>();
    const Status s = decode("df::msg::RgbdFrame", bytes, *out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_EQ(s.message(), std::string(kWhere) + ": CDR data is not a valid df::msg::RgbdFrame");
}

/// CDR of a CompressedImage of 4x2 pixels with 16 bytes of data.
std::vector<uint8_t> compressed_bytes(uint16_t width) {
    df_msg_CompressedImage c{};
    std::vector<uint8_t> data(16, 7);
    c.width = width;
    c.height = 2;
    dds::set_name(c.format, "png");
    c.data._buffer = data.data();
    c.data._length = static_cast<uint32_t>(data.size());
    c.data._maximum = c.data._length;
    return dds::to_cdr(&df_msg_CompressedImage_desc, &c);
}

TEST(RecordedSample, ACompressedImageOfAnImpossibleSizeIsRefused) {
    df_msg_CompressedImage out{};
    const Status s = decode("df::msg::CompressedImage", compressed_bytes(1000), out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_EQ(s.message(), std::string(kWhere) + ": CompressedImage.width 1000 > MAX_WIDTH 640");
}

TEST(RecordedSample, ACompressedImageWhoseDataLengthLiesIsRefused) {
    auto bytes = compressed_bytes(4);
    // 4 bytes encapsulation + Header (40) + 4 uint16 + format[8]: the sequence length.
    constexpr size_t kLengthAt = 4 + 40 + 8 + 8;
    uint32_t length = 0;
    std::memcpy(&length, bytes.data() + kLengthAt, 4);
    ASSERT_EQ(length, 16U) << "the CDR layout of CompressedImage changed";
    length = df_msg_MAX_RGB_BYTES + 1;  // more than the bound and than the bytes there
    std::memcpy(bytes.data() + kLengthAt, &length, 4);
    df_msg_CompressedImage out{};
    const Status s = decode("df::msg::CompressedImage", bytes, out);
    ASSERT_FALSE(s.is_ok());
    EXPECT_EQ(s.message(),
              std::string(kWhere) + ": CDR data is not a valid df::msg::CompressedImage");
}

}  // namespace
}  // namespace df::tap
