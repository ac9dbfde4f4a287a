// Truncated and corrupt files: the reader returns an error that names the file and a byte
// offset, and never crashes (every truncation length, every flipped byte).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_records.hpp"
#include "mcap/mcap_writer.hpp"
#include "mcap_test_util.hpp"

namespace df::mcap {
namespace {

using Compression = WriterOptions::Compression;

/// A small valid file: two channels, 12 messages in several chunks.
std::vector<uint8_t> make_file(Compression compression) {
    const std::string path = test::temp_path("corrupt_source.mcap");
    {
        WriterOptions options;
        options.chunk_size_bytes = 600;
        options.compression = compression;
        auto writer = Writer::open(path, options);
        EXPECT_TRUE(writer.is_ok());
        Writer& w = **writer;
        const uint16_t schema =
            w.add_schema("df::msg::Pose", "omgidl", "struct Pose { double x; };").value();
        const uint16_t a = w.add_channel(schema, "/a", "cdr").value();
        const uint16_t b = w.add_channel(schema, "/b", "cdr").value();
        for (uint32_t i = 0; i < 12; ++i) {
            const auto data = test::cdr_payload(40 + 20 * i, i);
            EXPECT_TRUE(
                w.write(i % 2 ? a : b, i, 1000 + i, 999 + i, data.data(), data.size()).is_ok());
        }
        EXPECT_TRUE(w.close().is_ok());
    }
    auto bytes = test::read_file(path);
    std::remove(path.c_str());
    return bytes;
}

/// Opens the file and reads every message; returns the first error (or ok).
Status open_and_read(const std::string& path) {
    auto reader = Reader::open(path);
    if (!reader.is_ok()) return reader.status();
    return (*reader)->for_each_message([](const Message&) { return true; });
}

uint64_t le64_at(const std::vector<uint8_t>& b, size_t at) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(b[at + i]) << (8 * i);
    return v;
}

/// Offset of the first Chunk record: after the magic and the Header record.
size_t first_chunk_offset(const std::vector<uint8_t>& b) {
    const size_t after_header = 8 + 9 + le64_at(b, 9);
    EXPECT_EQ(b[after_header], uint8_t(detail::Op::kChunk));
    return after_header;
}

void expect_error_at(const Status& s, const std::string& path, const std::string& needle) {
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("'" + path + "'"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
}

TEST(McapCorrupt, MissingFileIsNotFound) {
    auto reader = Reader::open("/nonexistent/recording.mcap");
    ASSERT_FALSE(reader.is_ok());
    EXPECT_EQ(reader.status().code(), StatusCode::kNotFound);
    EXPECT_NE(reader.status().message().find("/nonexistent/recording.mcap"), std::string::npos);
}

TEST(McapCorrupt, NotAnMcapFile) {
    const std::string path = test::temp_path("text.mcap");
    const std::string text = "hello, this is not an mcap file";
    test::write_file(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
    expect_error_at(open_and_read(path), path, "byte 0: not an MCAP file");
    std::remove(path.c_str());
}

TEST(McapCorrupt, EveryTruncationFailsNamingFileAndOffset) {
    const auto bytes = make_file(Compression::kNone);
    const std::string path = test::temp_path("truncated.mcap");
    for (size_t length = 0; length < bytes.size(); ++length) {
        test::write_file(path, bytes.data(), length);
        const Status s = open_and_read(path);
        SCOPED_TRACE("truncated to " + std::to_string(length) + " of " +
                     std::to_string(bytes.size()));
        expect_error_at(s, path, "byte ");
        if (HasFailure()) break;
    }
    // A recording cut at a record boundary (writer never closed): no Footer.
    const size_t chunk = first_chunk_offset(bytes);
    const size_t after_chunk = chunk + 9 + le64_at(bytes, chunk + 1);
    test::write_file(path, bytes.data(), after_chunk);
    expect_error_at(open_and_read(path), path,
                    "byte " + std::to_string(after_chunk) + ": file ends without a Footer");
    std::remove(path.c_str());
}

TEST(McapCorrupt, FlippedByteInChunkFailsTheChunkCrc) {
    auto bytes = make_file(Compression::kNone);
    const size_t chunk = first_chunk_offset(bytes);
    const size_t chunk_end = chunk + 9 + le64_at(bytes, chunk + 1);
    bytes[chunk_end - 3] ^= 0x01;  // inside the last message's data
    const std::string path = test::temp_path("chunk_crc.mcap");
    test::write_file(path, bytes.data(), bytes.size());
    expect_error_at(open_and_read(path), path,
                    "byte " + std::to_string(chunk) + ": chunk CRC mismatch");
    std::remove(path.c_str());
}

TEST(McapCorrupt, FlippedByteInSummaryFailsTheSummaryCrc) {
    auto bytes = make_file(Compression::kNone);
    const uint64_t summary_start = le64_at(bytes, bytes.size() - 8 - 20);
    bytes[summary_start + 20] ^= 0x20;  // inside the first summary Schema's name
    const std::string path = test::temp_path("summary_crc.mcap");
    test::write_file(path, bytes.data(), bytes.size());
    expect_error_at(open_and_read(path), path,
                    "byte " + std::to_string(summary_start) + ": summary CRC mismatch");
    std::remove(path.c_str());
}

TEST(McapCorrupt, RecordLengthPastEndOfFile) {
    auto bytes = make_file(Compression::kNone);
    const size_t chunk = first_chunk_offset(bytes);
    bytes[chunk + 8] = 0x40;  // top byte of the length: ~4.6e18 bytes
    const std::string path = test::temp_path("length.mcap");
    test::write_file(path, bytes.data(), bytes.size());
    expect_error_at(open_and_read(path), path,
                    "byte " + std::to_string(chunk) + ": Chunk (0x06) record claims");
    std::remove(path.c_str());
}

TEST(McapCorrupt, EveryFlippedByteIsHandledWithoutCrashing) {
    for (Compression c : {Compression::kNone, Compression::kZstd}) {
        const auto bytes = make_file(c);
        const std::string path = test::temp_path("flip.mcap");
        size_t detected = 0;
        for (size_t i = 0; i < bytes.size(); ++i) {
            auto corrupt = bytes;
            corrupt[i] ^= 0xFF;
            test::write_file(path, corrupt.data(), corrupt.size());
            const Status s = open_and_read(path);
            if (!s.is_ok()) {
                ++detected;
                ASSERT_NE(s.message().find(path), std::string::npos) << s.message();
            }
        }
        // Only bytes that nothing checks (MessageIndex records, chunk time fields, the DataEnd
        // CRC) may go unnoticed.
        EXPECT_GT(detected, bytes.size() * 3 / 4) << "of " << bytes.size();
        std::remove(path.c_str());
    }
}

}  // namespace
}  // namespace df::mcap
