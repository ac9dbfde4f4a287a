#pragma once
/// Internal to df_mcap: record opcodes, little-endian field encoding and decoding, CRC-32.
/// Written from the MCAP specification (https://mcap.dev/spec), major version 0.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mcap/mcap_types.hpp"

namespace df::mcap::detail {

enum class Op : uint8_t {
    kHeader = 0x01,
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kMessageIndex = 0x07,
    kChunkIndex = 0x08,
    kAttachment = 0x09,
    kAttachmentIndex = 0x0A,
    kStatistics = 0x0B,
    kMetadata = 0x0C,
    kMetadataIndex = 0x0D,
    kSummaryOffset = 0x0E,
    kDataEnd = 0x0F,
};

/// "\x89MCAP0\r\n": starts and ends every file.
inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
/// Every record: opcode (1 byte) + content length (uint64).
inline constexpr size_t kRecordPrefixBytes = 9;
/// Message record fields before the data: channel_id, sequence, log_time, publish_time.
inline constexpr size_t kMessageFieldsBytes = 2 + 4 + 8 + 8;
/// Footer content: summary_start, summary_offset_start, summary_crc.
inline constexpr size_t kFooterBytes = 8 + 8 + 4;

/// "Chunk (0x06)" etc., for error messages.
std::string op_name(uint8_t op);

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as MCAP uses it.
class Crc32 {
  public:
    void update(const uint8_t* data, size_t size);
    uint32_t value() const { return ~state_; }

  private:
    uint32_t state_ = 0xFFFFFFFFu;
};
uint32_t crc32(const uint8_t* data, size_t size);

/// Appends little-endian fields to a byte buffer.
class ByteWriter {
  public:
    explicit ByteWriter(std::vector<uint8_t>& out) : out_(out) {}
    void u8(uint8_t v) { out_.push_back(v); }
    void u16(uint16_t v) { put(v, 2); }
    void u32(uint32_t v) { put(v, 4); }
    void u64(uint64_t v) { put(v, 8); }
    void bytes(const void* data, size_t size);
    /// uint32 length + bytes.
    void str(const std::string& s);
    void string_map(const std::map<std::string, std::string>& m);
    /// Writes opcode and a length placeholder; returns where the content starts.
    size_t begin_record(Op op);
    /// Patches the length of the record whose content started at `content_start`.
    void end_record(size_t content_start);
    /// Reserves a uint32 byte-length prefix (arrays, maps); returns where the elements start.
    size_t begin_u32_length();
    void end_u32_length(size_t elements_start);

  private:
    void put(uint64_t v, int bytes);
    std::vector<uint8_t>& out_;
};

/// Reads little-endian fields from a byte range; every read is bounds-checked and returns false
/// (leaving the position unchanged) when the range is too short.
class ByteReader {
  public:
    ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    bool u8(uint8_t& v);
    bool u16(uint16_t& v);
    bool u32(uint32_t& v);
    bool u64(uint64_t& v);
    bool str(std::string& s);
    bool string_map(std::map<std::string, std::string>& m);
    bool skip(size_t n);
    size_t pos() const { return pos_; }
    size_t remaining() const { return size_ - pos_; }
    const uint8_t* here() const { return data_ + pos_; }

  private:
    bool get(uint64_t& v, int bytes);
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

/// Fixed fields of a Chunk record that precede its records.
struct ChunkHeader {
    uint64_t message_start_time = 0;
    uint64_t message_end_time = 0;
    uint64_t uncompressed_size = 0;
    uint32_t uncompressed_crc = 0;
    std::string compression;
    uint64_t records_size = 0;
    size_t records_offset = 0;  ///< where `records` starts, from the start of the content
};

struct MessageFields {
    uint16_t channel_id = 0;
    uint32_t sequence = 0;
    uint64_t log_time = 0;
    uint64_t publish_time = 0;
};

// Record content encoders (opcode and length included) and decoders (content only; false when
// the content is too short or a length field runs past its end).
void encode_schema(std::vector<uint8_t>& out, const Schema& s);
void encode_channel(std::vector<uint8_t>& out, const Channel& c);
void encode_message_prefix(std::vector<uint8_t>& out, const MessageFields& m, size_t data_size);
bool decode_schema(const uint8_t* content, size_t size, Schema& s);
bool decode_channel(const uint8_t* content, size_t size, Channel& c);
bool decode_message_fields(const uint8_t* content, size_t size, MessageFields& m);
/// Decodes the fields before `records`; does not check that records_size fits the record.
bool decode_chunk_header(const uint8_t* content, size_t size, ChunkHeader& h);
bool decode_statistics(const uint8_t* content, size_t size, Statistics& s);

}  // namespace df::mcap::detail
