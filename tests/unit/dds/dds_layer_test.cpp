// The DDS layer without shared memory: errors as values, QoS profiles, CDR round trips, typed
// writer/reader in one process, and a clear error when shared memory is asked for without RouDi.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "dds/cdr.hpp"
#include "dds/dds_error.hpp"
#include "dds/msg_convert.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"

namespace df::dds {
namespace {

std::string unique(const std::string& stem) {
    static int n = 0;
    return "u" + std::to_string(::getpid()) + "_" + std::to_string(n++) + "/" + stem;
}

Participant udp_participant(uint32_t domain) {
    ParticipantConfig pc;
    pc.domain_id = domain;
    pc.transport = Transport::kUdp;
    auto p = Participant::create(pc);
    EXPECT_TRUE(p.is_ok()) << p.status().to_string();
    return std::move(*p);
}

TEST(DdsError, ReturnCodesBecomeStatusesWithContext) {
    EXPECT_TRUE(check(DDS_RETCODE_OK, "x").is_ok());
    EXPECT_TRUE(check(5, "a count").is_ok());
    const Status s = check(DDS_RETCODE_BAD_PARAMETER, "creating reader on 'a/b'");
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("creating reader on 'a/b'"), std::string::npos);
    EXPECT_EQ(check(DDS_RETCODE_TIMEOUT, "w").code(), StatusCode::kTimeout);
    EXPECT_EQ(check(DDS_RETCODE_OUT_OF_RESOURCES, "w").code(), StatusCode::kResourceExhausted);
}

TEST(Qos, EveryProfileIsShmCompatible) {
    for (auto profile :
         {QosProfile::kFrames, QosProfile::kResults, QosProfile::kStatus, QosProfile::kTap}) {
        QosPtr q = make_qos(profile);
        dds_history_kind_t hist;
        int32_t depth = 0;
        ASSERT_TRUE(dds_qget_history(q.get(), &hist, &depth));
        EXPECT_EQ(hist, DDS_HISTORY_KEEP_LAST);
        EXPECT_GT(depth, 0);
        dds_durability_kind_t dur;
        ASSERT_TRUE(dds_qget_durability(q.get(), &dur));
        EXPECT_EQ(dur, DDS_DURABILITY_VOLATILE);
    }
    dds_reliability_kind_t rel;
    dds_duration_t blocking;
    QosPtr tap = make_qos(QosProfile::kTap);
    ASSERT_TRUE(dds_qget_reliability(tap.get(), &rel, &blocking));
    EXPECT_EQ(rel, DDS_RELIABILITY_BEST_EFFORT);
    QosPtr frames = make_qos(QosProfile::kFrames, 9);
    dds_history_kind_t hist;
    int32_t depth = 0;
    ASSERT_TRUE(dds_qget_history(frames.get(), &hist, &depth));
    EXPECT_EQ(depth, 9);
}

TEST(Transport, ParsesNamesAndRejectsOthers) {
    EXPECT_EQ(*parse_transport("shm"), Transport::kSharedMemory);
    EXPECT_EQ(*parse_transport("udp"), Transport::kUdp);
    EXPECT_EQ(*parse_transport("auto"), Transport::kAuto);
    auto bad = parse_transport("tcp");
    ASSERT_FALSE(bad.is_ok());
    EXPECT_NE(bad.status().message().find("tcp"), std::string::npos);
}

TEST(Participant, SharedMemoryWithoutRoudiIsAClearErrorNotAnAbort) {
    ParticipantConfig pc;
    pc.transport = Transport::kSharedMemory;
    pc.roudi_lock_file = "/nonexistent/roudi.lock";
    auto p = Participant::create(pc);
    ASSERT_FALSE(p.is_ok());
    EXPECT_EQ(p.status().code(), StatusCode::kUnavailable);
    EXPECT_NE(p.status().message().find("iox-roudi"), std::string::npos) << p.status().message();
}

TEST(Names, FixedCharArraysAreTruncatedAndTerminated) {
    char name[8];
    set_name(name, "capture");
    EXPECT_EQ(get_name(name), "capture");
    set_name(name, "a-very-long-stage-name");
    EXPECT_EQ(get_name(name), "a-very-");
    EXPECT_EQ(topic_name("df", "frames"), "df/frames");
    EXPECT_EQ(topic_name("", "frames"), "frames");
}

TEST(TypeTable, EveryTypeIsKnownAndImageTypesAreLoanable) {
    for (const auto& t : all_types()) EXPECT_EQ(find_type(t.name), &t);
    EXPECT_EQ(find_type("df::msg::Nope"), nullptr);
    for (const char* fixed :
         {"df::msg::RgbdFrame", "df::msg::GeometricSegments", "df::msg::ObjectSegments",
          "df::msg::Detections", "df::msg::CameraPose", "df::msg::StageStatus"}) {
        EXPECT_TRUE(find_type(fixed)->fixed_size()) << fixed << " must be fixed-size to be loaned";
    }
    EXPECT_FALSE(find_type("df::msg::CompressedImage")->fixed_size());
}

std::unique_ptr<df_msg_RgbdFrame> random_frame(uint64_t seq) {
    auto f = std::make_unique<df_msg_RgbdFrame>();
    std::memset(static_cast<void*>(f.get()), 0, sizeof *f);
    std::mt19937 rng(static_cast<unsigned>(seq));
    f->header.seq = seq;
    f->header.capture_ns = 1'700'000'000'000'000'000ULL + seq;
    f->header.sensor_ns = 42 + seq;
    f->header.status = df_msg_FRAME_OK;
    f->width = 640;
    f->height = 480;
    f->intrinsics = {535.4f, 539.2f, 320.1f, 247.6f};
    f->depth_units_per_m = 5000;
    for (auto& b : f->rgb) b = static_cast<uint8_t>(rng());
    for (auto& d : f->depth) d = static_cast<uint16_t>(rng());
    return f;
}

TEST(Cdr, FrameRoundTripIsByteIdentical) {
    auto f = random_frame(7);
    const std::vector<uint8_t> cdr = to_cdr(&df_msg_RgbdFrame_desc, f.get());
    ASSERT_GE(cdr.size(), 4 + sizeof(f->rgb) + sizeof(f->depth));
    EXPECT_EQ(cdr[0], 0);
    EXPECT_EQ(cdr[1], 1);  // CDR little endian
    auto back = std::make_unique<df_msg_RgbdFrame>();
    std::memset(static_cast<void*>(back.get()), 0, sizeof *back);
    ASSERT_TRUE(from_cdr(&df_msg_RgbdFrame_desc, cdr.data(), cdr.size(), back.get()).is_ok());
    EXPECT_EQ(std::memcmp(f.get(), back.get(), sizeof *f), 0);
}

TEST(Cdr, SequenceTypeRoundTrips) {
    df_msg_CompressedImage c{};
    std::vector<uint8_t> bytes = {1, 2, 3, 4, 5, 250};
    c.header.seq = 3;
    c.width = 320;
    set_name(c.format, "jpeg");
    c.data._buffer = bytes.data();
    c.data._length = c.data._maximum = static_cast<uint32_t>(bytes.size());
    const auto cdr = to_cdr(&df_msg_CompressedImage_desc, &c);
    df_msg_CompressedImage back{};
    ASSERT_TRUE(from_cdr(&df_msg_CompressedImage_desc, cdr.data(), cdr.size(), &back).is_ok());
    EXPECT_EQ(back.header.seq, 3U);
    EXPECT_EQ(back.width, 320);
    EXPECT_EQ(get_name(back.format), "jpeg");
    ASSERT_EQ(back.data._length, bytes.size());
    EXPECT_EQ(std::memcmp(back.data._buffer, bytes.data(), bytes.size()), 0);
    dds_sample_free(&back, &df_msg_CompressedImage_desc, DDS_FREE_CONTENTS);
}

TEST(Cdr, TruncatedOrForeignDataIsRejected) {
    auto f = random_frame(1);
    std::vector<uint8_t> cdr = to_cdr(&df_msg_RgbdFrame_desc, f.get());
    auto out = std::make_unique<df_msg_RgbdFrame>();
    EXPECT_FALSE(from_cdr(&df_msg_RgbdFrame_desc, cdr.data(), 3, out.get()).is_ok());
    EXPECT_FALSE(from_cdr(&df_msg_RgbdFrame_desc, cdr.data(), cdr.size() / 2, out.get()).is_ok());
    std::vector<uint8_t> big_endian = cdr;
    big_endian[1] = 0;
    EXPECT_FALSE(
        from_cdr(&df_msg_RgbdFrame_desc, big_endian.data(), big_endian.size(), out.get()).is_ok());
    // A sequence longer than its bound must not be accepted.
    df_msg_CompressedImage c{};
    std::vector<uint8_t> bytes(16, 7);
    c.data._buffer = bytes.data();
    c.data._length = c.data._maximum = 16;
    auto seq = to_cdr(&df_msg_CompressedImage_desc, &c);
    const size_t len_offset = 4 + sizeof(df_msg_Header) + 4 * 2 + 8;  // header, 4 uint16, char[8]
    uint32_t huge = 2'000'000;
    ASSERT_LT(len_offset + 4, seq.size());
    std::memcpy(seq.data() + len_offset, &huge, 4);
    df_msg_CompressedImage back{};
    EXPECT_FALSE(from_cdr(&df_msg_CompressedImage_desc, seq.data(), seq.size(), &back).is_ok());
}

TEST(WriterReader, FramesArriveIntactInOneProcessOverUdp) {
    Participant p = udp_participant(11);
    const std::string topic = unique("frames");
    auto reader = Reader<df_msg_RgbdFrame>::create(p, topic, {QosProfile::kFrames, 8});
    auto writer = Writer<df_msg_RgbdFrame>::create(p, topic);
    ASSERT_TRUE(reader.is_ok() && writer.is_ok());
    EXPECT_FALSE(writer->loans_shared_memory());  // no shared memory: heap samples, copied
    ASSERT_TRUE(wait_for_matches(writer->get(), true, 1, DDS_SECS(5)).is_ok());
    auto ws = WaitSet::create(p);
    ASSERT_TRUE(ws.is_ok() && ws->attach_reader(reader->get()).is_ok());
    for (uint64_t i = 0; i < 3; ++i) {
        auto loan = writer->loan();
        ASSERT_TRUE(loan.is_ok());
        EXPECT_FALSE(loan->shared_memory());
        auto f = random_frame(i);
        std::memcpy(static_cast<void*>(loan->get()), f.get(), sizeof *f);
        ASSERT_TRUE(writer->write(std::move(*loan)).is_ok());
    }
    int got = 0;
    for (int tries = 0; tries < 50 && got < 3; ++tries) {
        (void)ws->wait(DDS_MSECS(100));
        (void)reader->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            auto expected = random_frame(static_cast<uint64_t>(got));
            EXPECT_EQ(std::memcmp(&f, expected.get(), sizeof f), 0) << "frame " << got;
            ++got;
        });
    }
    EXPECT_EQ(got, 3);
}

TEST(WriterReader, BadTopicNameIsAnErrorValue) {
    Participant p = udp_participant(12);
    auto w = Writer<df_msg_CameraPose>::create(p, "bad-name/with-dashes");
    ASSERT_FALSE(w.is_ok());
    EXPECT_NE(w.status().message().find("bad-name/with-dashes"), std::string::npos);
}

TEST(MsgConvert, FrameViewsAliasTheSample) {
    io::RgbdImage img;
    img.rgb = cv::Mat(4, 6, CV_8UC3, cv::Scalar(1, 2, 3));
    img.depth = cv::Mat(4, 6, CV_16UC1, cv::Scalar(1234));
    img.intrinsics = {100, 101, 3, 2};
    img.depth_units_per_m = 1000;
    auto f = std::make_unique<df_msg_RgbdFrame>();
    df_msg_Header h{};
    h.seq = 9;
    fill_frame(img, h, f.get());
    EXPECT_EQ(f->width, 6);
    EXPECT_EQ(f->height, 4);
    EXPECT_EQ(f->rgb[0], 1);
    EXPECT_EQ(f->rgb[2], 3);
    EXPECT_EQ(f->depth[23], 1234);
    EXPECT_FLOAT_EQ(f->intrinsics.fy, 101);
    const auto back = to_image(*f);
    ASSERT_TRUE(back) << back.status().to_string();
    EXPECT_EQ(cv::norm(back->rgb, img.rgb, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(back->depth, img.depth, cv::NORM_INF), 0);
    EXPECT_EQ(back->index, 9U);
}

}  // namespace
}  // namespace df::dds
