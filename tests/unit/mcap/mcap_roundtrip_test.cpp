// Round trips through df::mcap::Writer and df::mcap::Reader: what was written comes back byte for
// byte, in log-time order, with and without zstd; plus hand-built files in shapes our writer
// does not produce (top-level messages, chunks without a summary).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_records.hpp"
#include "mcap/mcap_writer.hpp"
#include "mcap_test_util.hpp"

namespace df::mcap {
namespace {

using test::WrittenMessage;
using Compression = WriterOptions::Compression;

const std::string kFrameIdl =
    "module df { module msg { struct RgbdFrame { uint64 stamp_ns; }; }; };";
const std::string kPoseIdl = "module df { module msg { struct Pose { double xyz[3]; }; }; };";

std::vector<WrittenMessage> read_all(Reader& reader) {
    std::vector<WrittenMessage> out;
    const Status status = reader.for_each_message([&](const Message& m) {
        out.push_back({m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns,
                       std::vector<uint8_t>(m.data, m.data + m.size)});
        return true;
    });
    EXPECT_TRUE(status.is_ok()) << status.to_string();
    return out;
}

void expect_same_messages(const std::vector<WrittenMessage>& expected,
                          const std::vector<WrittenMessage>& actual) {
    ASSERT_EQ(expected.size(), actual.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        SCOPED_TRACE("message " + std::to_string(i));
        EXPECT_EQ(expected[i].channel_id, actual[i].channel_id);
        EXPECT_EQ(expected[i].sequence, actual[i].sequence);
        EXPECT_EQ(expected[i].log_time_ns, actual[i].log_time_ns);
        EXPECT_EQ(expected[i].publish_time_ns, actual[i].publish_time_ns);
        EXPECT_TRUE(expected[i].data == actual[i].data);
    }
}

class RoundTrip : public ::testing::TestWithParam<Compression> {};

TEST_P(RoundTrip, SchemasChannelsAndMessagesComeBackByteIdenticalInLogTimeOrder) {
    const std::string path = test::temp_path("roundtrip.mcap");
    WriterOptions options;
    options.profile = "x-detectfusion";
    options.chunk_size_bytes = 4096;
    options.compression = GetParam();

    std::vector<WrittenMessage> written;
    {
        auto writer = Writer::open(path, options);
        ASSERT_TRUE(writer.is_ok()) << writer.status().to_string();
        Writer& w = **writer;
        const uint16_t frame = w.add_schema("df::msg::RgbdFrame", "omgidl", kFrameIdl).value();
        const uint16_t pose = w.add_schema("df::msg::Pose", "omgidl", kPoseIdl).value();
        EXPECT_EQ(w.add_schema("df::msg::RgbdFrame", "omgidl", kFrameIdl).value(), frame);
        const uint16_t rgbd =
            w.add_channel(frame, "/camera/rgbd", "cdr", {{"qos", "reliable"}}).value();
        const uint16_t poses = w.add_channel(pose, "/slam/pose", "cdr").value();
        const uint16_t raw = w.add_channel(0, "/debug/raw", "cdr").value();
        const uint16_t channels[] = {rgbd, poses, raw};
        for (uint32_t i = 0; i < 60; ++i) {
            // Log times out of order and with ties; every 15th message is larger than a chunk.
            const uint64_t log_time = 1'700'000'000'000'000'000ull + (i * 37 % 25) * 1'000'000;
            const size_t size = i % 15 == 7 ? 10'000 : (i * 53) % 300;
            written.push_back(
                {channels[i % 3], i, log_time, log_time - 500, test::cdr_payload(size, i)});
            const WrittenMessage& m = written.back();
            ASSERT_TRUE(w.write(m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns,
                                m.data.data(), m.data.size())
                            .is_ok());
        }
        EXPECT_EQ(w.message_count(), 60u);
        const Status closed = w.close();
        ASSERT_TRUE(closed.is_ok()) << closed.to_string();
    }

    auto reader = Reader::open(path);
    ASSERT_TRUE(reader.is_ok()) << reader.status().to_string();
    Reader& r = **reader;
    EXPECT_EQ(r.profile(), "x-detectfusion");
    EXPECT_EQ(r.library(), "detectfusion");
    const std::map<uint16_t, Schema> schemas = {{1, {1, "df::msg::RgbdFrame", "omgidl", kFrameIdl}},
                                                {2, {2, "df::msg::Pose", "omgidl", kPoseIdl}}};
    EXPECT_EQ(r.schemas(), schemas);
    const std::map<uint16_t, Channel> channels = {
        {1, {1, 1, "/camera/rgbd", "cdr", {{"qos", "reliable"}}}},
        {2, {2, 2, "/slam/pose", "cdr", {}}},
        {3, {3, 0, "/debug/raw", "cdr", {}}}};
    EXPECT_EQ(r.channels(), channels);
    ASSERT_TRUE(r.statistics().has_value());
    EXPECT_EQ(r.statistics()->message_count, 60u);
    EXPECT_EQ(r.statistics()->channel_message_counts,
              (std::map<uint16_t, uint64_t>{{1, 20}, {2, 20}, {3, 20}}));
    EXPECT_EQ(r.statistics()->message_start_time_ns, written[0].log_time_ns);  // i = 0: offset 0
    EXPECT_GT(r.statistics()->chunk_count, 4u);

    std::vector<WrittenMessage> expected = written;
    std::stable_sort(expected.begin(), expected.end(),
                     [](const auto& a, const auto& b) { return a.log_time_ns < b.log_time_ns; });
    expect_same_messages(expected, read_all(r));
    // A second pass reads the same again.
    expect_same_messages(expected, read_all(r));
    std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(Compressions, RoundTrip,
                         ::testing::Values(Compression::kNone, Compression::kZstd),
                         [](const auto& param_info) {
                             return param_info.param == Compression::kNone ? "None" : "Zstd";
                         });

TEST(McapWriter, MessageLargerThanChunkSizeGetsAChunkOfItsOwn) {
    const std::string path = test::temp_path("big.mcap");
    WriterOptions options;
    options.chunk_size_bytes = 1000;
    {
        auto writer = Writer::open(path, options);
        ASSERT_TRUE(writer.is_ok());
        const uint16_t ch = (*writer)->add_channel(0, "/t", "cdr").value();
        const auto small = test::cdr_payload(100, 1);
        const auto big = test::cdr_payload(5000, 2);
        ASSERT_TRUE((*writer)->write(ch, 0, 10, 10, small.data(), small.size()).is_ok());
        ASSERT_TRUE((*writer)->write(ch, 1, 20, 20, small.data(), small.size()).is_ok());
        ASSERT_TRUE((*writer)->write(ch, 2, 30, 30, big.data(), big.size()).is_ok());
        ASSERT_TRUE((*writer)->write(ch, 3, 40, 40, small.data(), small.size()).is_ok());
    }  // the destructor closes the file
    auto reader = Reader::open(path);
    ASSERT_TRUE(reader.is_ok()) << reader.status().to_string();
    // [small, small] [big] [small]
    EXPECT_EQ((*reader)->statistics()->chunk_count, 3u);
    const auto messages = read_all(**reader);
    ASSERT_EQ(messages.size(), 4u);
    EXPECT_EQ(messages[2].data, test::cdr_payload(5000, 2));
    std::remove(path.c_str());
}

TEST(McapWriter, ZstdMakesCompressibleChunksSmaller) {
    std::vector<uint64_t> sizes;
    for (Compression c : {Compression::kNone, Compression::kZstd}) {
        const std::string path = test::temp_path("zstd_size.mcap");
        WriterOptions options;
        options.compression = c;
        auto writer = Writer::open(path, options);
        ASSERT_TRUE(writer.is_ok());
        const uint16_t ch = (*writer)->add_channel(0, "/depth", "cdr").value();
        const std::vector<uint8_t> flat_depth(640 * 480 * 2, 0x7F);
        ASSERT_TRUE((*writer)->write(ch, 0, 1, 1, flat_depth.data(), flat_depth.size()).is_ok());
        ASSERT_TRUE((*writer)->close().is_ok());
        sizes.push_back((*writer)->bytes_written());
        std::remove(path.c_str());
    }
    EXPECT_LT(sizes[1] * 10, sizes[0]);
}

TEST(McapWriter, EmptyFileIsValid) {
    const std::string path = test::temp_path("empty.mcap");
    ASSERT_TRUE(Writer::open(path).value()->close().is_ok());
    auto reader = Reader::open(path);
    ASSERT_TRUE(reader.is_ok()) << reader.status().to_string();
    EXPECT_TRUE((*reader)->schemas().empty());
    EXPECT_TRUE((*reader)->channels().empty());
    EXPECT_EQ((*reader)->statistics()->message_count, 0u);
    EXPECT_TRUE(read_all(**reader).empty());
    std::remove(path.c_str());
}

TEST(McapWriter, RejectsUnknownIdsAndUseAfterClose) {
    const std::string path = test::temp_path("reject.mcap");
    auto writer = Writer::open(path);
    ASSERT_TRUE(writer.is_ok());
    Writer& w = **writer;
    const uint8_t byte = 0;
    EXPECT_EQ(w.add_channel(42, "/t", "cdr").status().code(), StatusCode::kInvalidArgument);
    const Status unknown = w.write(7, 0, 0, 0, &byte, 1);
    EXPECT_EQ(unknown.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(unknown.message().find(path), std::string::npos) << unknown.message();
    ASSERT_TRUE(w.close().is_ok());
    EXPECT_FALSE(w.add_schema("a", "omgidl", "x").is_ok());
    EXPECT_FALSE(w.write(1, 0, 0, 0, &byte, 1).is_ok());
    EXPECT_TRUE(w.close().is_ok());  // again: the first result

    auto missing_dir = Writer::open("/nonexistent-dir/x.mcap");
    ASSERT_FALSE(missing_dir.is_ok());
    EXPECT_NE(missing_dir.status().message().find("/nonexistent-dir/x.mcap"), std::string::npos);
    std::remove(path.c_str());
}

TEST(McapReader, StopsWhenTheCallbackReturnsFalse) {
    const std::string path = test::temp_path("stop.mcap");
    {
        auto writer = Writer::open(path);
        const uint16_t ch = (*writer)->add_channel(0, "/t", "cdr").value();
        for (uint32_t i = 0; i < 10; ++i)
            ASSERT_TRUE((*writer)->write(ch, i, i, i, nullptr, 0).is_ok());
    }
    auto reader = Reader::open(path);
    ASSERT_TRUE(reader.is_ok());
    int calls = 0;
    EXPECT_TRUE((*reader)->for_each_message([&](const Message&) { return ++calls < 3; }).is_ok());
    EXPECT_EQ(calls, 3);
    std::remove(path.c_str());
}

// Builds files by hand in shapes our writer does not produce. No summary: Footer(0, 0, 0).
std::vector<uint8_t> hand_built(bool chunked) {
    using detail::ByteWriter;
    using detail::Op;
    std::vector<uint8_t> records;
    detail::encode_schema(records, {1, "S", "omgidl", kPoseIdl});
    detail::encode_channel(records, {5, 1, "/top", "cdr", {}});
    const uint8_t payload_b[] = {0, 1, 0, 0, 0xBB};
    const uint8_t payload_a[] = {0, 1, 0, 0, 0xAA, 0xAA};
    detail::encode_message_prefix(records, {5, 2, 200, 190}, sizeof(payload_b));
    records.insert(records.end(), payload_b, payload_b + sizeof(payload_b));
    detail::encode_message_prefix(records, {5, 1, 100, 90}, sizeof(payload_a));
    records.insert(records.end(), payload_a, payload_a + sizeof(payload_a));

    std::vector<uint8_t> file;
    ByteWriter w(file);
    w.bytes(detail::kMagic, 8);
    size_t start = w.begin_record(Op::kHeader);
    w.str("");
    w.str("hand");
    w.end_record(start);
    if (chunked) {
        start = w.begin_record(Op::kChunk);
        w.u64(100);
        w.u64(200);
        w.u64(records.size());
        w.u32(detail::crc32(records.data(), records.size()));
        w.str("");
        w.u64(records.size());
        w.bytes(records.data(), records.size());
        w.end_record(start);
    } else {
        w.bytes(records.data(), records.size());
    }
    start = w.begin_record(Op::kDataEnd);
    w.u32(0);
    w.end_record(start);
    start = w.begin_record(Op::kFooter);
    w.u64(0);
    w.u64(0);
    w.u32(0);
    w.end_record(start);
    w.bytes(detail::kMagic, 8);
    return file;
}

TEST(McapReader, ReadsTopLevelMessagesAndChunksWithoutSummary) {
    for (bool chunked : {false, true}) {
        SCOPED_TRACE(chunked ? "chunked" : "top-level");
        const std::string path = test::temp_path("hand.mcap");
        const auto bytes = hand_built(chunked);
        test::write_file(path, bytes.data(), bytes.size());
        auto reader = Reader::open(path);
        ASSERT_TRUE(reader.is_ok()) << reader.status().to_string();
        EXPECT_EQ((*reader)->library(), "hand");
        EXPECT_FALSE((*reader)->statistics().has_value());
        ASSERT_EQ((*reader)->schemas().size(), 1u);
        ASSERT_EQ((*reader)->channels().count(5), 1u);
        EXPECT_EQ((*reader)->channels().at(5).topic, "/top");
        const auto messages = read_all(**reader);
        ASSERT_EQ(messages.size(), 2u);
        EXPECT_EQ(messages[0].log_time_ns, 100u);
        EXPECT_EQ(messages[0].publish_time_ns, 90u);
        EXPECT_EQ(messages[0].data, (std::vector<uint8_t>{0, 1, 0, 0, 0xAA, 0xAA}));
        EXPECT_EQ(messages[1].sequence, 2u);
        std::remove(path.c_str());
    }
}

TEST(Crc32, MatchesTheStandardCheckValue) {
    const std::string check = "123456789";
    EXPECT_EQ(detail::crc32(reinterpret_cast<const uint8_t*>(check.data()), check.size()),
              0xCBF43926u);
    // Slice-by-8 and byte-wise paths agree when the input is fed in odd pieces.
    const auto data = test::cdr_payload(1001, 3);
    detail::Crc32 pieces;
    for (size_t i = 0; i < data.size(); i += 7)
        pieces.update(data.data() + i, std::min<size_t>(7, data.size() - i));
    EXPECT_EQ(pieces.value(), detail::crc32(data.data(), data.size()));
}

}  // namespace
}  // namespace df::mcap
