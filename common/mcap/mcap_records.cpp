#include "mcap/mcap_records.hpp"

#include <array>
#include <cstdio>
#include <cstring>

namespace df::mcap::detail {

std::string op_name(uint8_t op) {
    static constexpr const char* kNames[] = {
        "?",        "Header",        "Footer",        "Schema",     "Channel",         "Message",
        "Chunk",    "MessageIndex",  "ChunkIndex",    "Attachment", "AttachmentIndex", "Statistics",
        "Metadata", "MetadataIndex", "SummaryOffset", "DataEnd"};
    char code[8];
    std::snprintf(code, sizeof(code), "0x%02X", op);
    const char* name = op < sizeof(kNames) / sizeof(kNames[0]) && op != 0 ? kNames[op] : "unknown";
    return std::string(name) + " (" + code + ")";
}

namespace {

using CrcTables = std::array<std::array<uint32_t, 256>, 8>;

// Slice-by-8 tables: table[k][b] is the CRC of byte b followed by k zero bytes.
CrcTables make_crc_tables() {
    CrcTables t{};
    for (uint32_t i = 0; i < 256; ++i) {
        uint32_t c = i;
        for (int bit = 0; bit < 8; ++bit) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
        t[0][i] = c;
    }
    for (size_t k = 1; k < 8; ++k) {
        for (size_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu];
    }
    return t;
}

uint32_t load_le32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

void Crc32::update(const uint8_t* p, size_t size) {
    static const CrcTables t = make_crc_tables();  // constant data, built once
    uint32_t c = state_;
    for (; size >= 8; p += 8, size -= 8) {
        const uint32_t a = load_le32(p) ^ c;
        const uint32_t b = load_le32(p + 4);
        c = t[7][a & 0xFF] ^ t[6][(a >> 8) & 0xFF] ^ t[5][(a >> 16) & 0xFF] ^ t[4][a >> 24] ^
            t[3][b & 0xFF] ^ t[2][(b >> 8) & 0xFF] ^ t[1][(b >> 16) & 0xFF] ^ t[0][b >> 24];
    }
    for (; size > 0; ++p, --size) c = (c >> 8) ^ t[0][(c ^ *p) & 0xFF];
    state_ = c;
}

uint32_t crc32(const uint8_t* data, size_t size) {
    Crc32 crc;
    crc.update(data, size);
    return crc.value();
}

// ---- ByteWriter ----

void ByteWriter::put(uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out_.push_back(uint8_t(v >> (8 * i)));
}

void ByteWriter::bytes(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    out_.insert(out_.end(), p, p + size);
}

void ByteWriter::str(const std::string& s) {
    u32(uint32_t(s.size()));
    bytes(s.data(), s.size());
}

void ByteWriter::string_map(const std::map<std::string, std::string>& m) {
    const size_t start = begin_u32_length();
    for (const auto& [key, value] : m) {
        str(key);
        str(value);
    }
    end_u32_length(start);
}

size_t ByteWriter::begin_record(Op op) {
    u8(uint8_t(op));
    u64(0);
    return out_.size();
}

void ByteWriter::end_record(size_t content_start) {
    const uint64_t length = out_.size() - content_start;
    for (int i = 0; i < 8; ++i) out_[content_start - 8 + i] = uint8_t(length >> (8 * i));
}

size_t ByteWriter::begin_u32_length() {
    u32(0);
    return out_.size();
}

void ByteWriter::end_u32_length(size_t elements_start) {
    const uint64_t length = out_.size() - elements_start;
    for (int i = 0; i < 4; ++i) out_[elements_start - 4 + i] = uint8_t(length >> (8 * i));
}

// ---- ByteReader ----

bool ByteReader::get(uint64_t& v, int bytes) {
    if (remaining() < size_t(bytes)) return false;
    v = 0;
    for (int i = 0; i < bytes; ++i) v |= uint64_t(data_[pos_ + i]) << (8 * i);
    pos_ += bytes;
    return true;
}

bool ByteReader::u8(uint8_t& v) {
    uint64_t x;
    if (!get(x, 1)) return false;
    v = uint8_t(x);
    return true;
}
bool ByteReader::u16(uint16_t& v) {
    uint64_t x;
    if (!get(x, 2)) return false;
    v = uint16_t(x);
    return true;
}
bool ByteReader::u32(uint32_t& v) {
    uint64_t x;
    if (!get(x, 4)) return false;
    v = uint32_t(x);
    return true;
}
bool ByteReader::u64(uint64_t& v) { return get(v, 8); }

bool ByteReader::skip(size_t n) {
    if (remaining() < n) return false;
    pos_ += n;
    return true;
}

bool ByteReader::str(std::string& s) {
    const size_t start = pos_;
    uint32_t n;
    if (!u32(n) || remaining() < n) {
        pos_ = start;
        return false;
    }
    s.assign(reinterpret_cast<const char*>(here()), n);
    pos_ += n;
    return true;
}

bool ByteReader::string_map(std::map<std::string, std::string>& m) {
    const size_t start = pos_;
    uint32_t n;
    if (!u32(n) || remaining() < n) {
        pos_ = start;
        return false;
    }
    ByteReader entries(here(), n);
    m.clear();
    while (entries.remaining() > 0) {
        std::string key, value;
        if (!entries.str(key) || !entries.str(value)) {
            pos_ = start;
            return false;
        }
        m[key] = value;
    }
    pos_ += n;
    return true;
}

// ---- records ----

void encode_schema(std::vector<uint8_t>& out, const Schema& s) {
    ByteWriter w(out);
    const size_t start = w.begin_record(Op::kSchema);
    w.u16(s.id);
    w.str(s.name);
    w.str(s.encoding);
    w.str(s.data);
    w.end_record(start);
}

void encode_channel(std::vector<uint8_t>& out, const Channel& c) {
    ByteWriter w(out);
    const size_t start = w.begin_record(Op::kChannel);
    w.u16(c.id);
    w.u16(c.schema_id);
    w.str(c.topic);
    w.str(c.message_encoding);
    w.string_map(c.metadata);
    w.end_record(start);
}

void encode_message_prefix(std::vector<uint8_t>& out, const MessageFields& m, size_t data_size) {
    ByteWriter w(out);
    w.u8(uint8_t(Op::kMessage));
    w.u64(kMessageFieldsBytes + data_size);
    w.u16(m.channel_id);
    w.u32(m.sequence);
    w.u64(m.log_time);
    w.u64(m.publish_time);
}

bool decode_schema(const uint8_t* content, size_t size, Schema& s) {
    ByteReader r(content, size);
    return r.u16(s.id) && r.str(s.name) && r.str(s.encoding) && r.str(s.data);
}

bool decode_channel(const uint8_t* content, size_t size, Channel& c) {
    ByteReader r(content, size);
    return r.u16(c.id) && r.u16(c.schema_id) && r.str(c.topic) && r.str(c.message_encoding) &&
           r.string_map(c.metadata);
}

bool decode_message_fields(const uint8_t* content, size_t size, MessageFields& m) {
    ByteReader r(content, size);
    return r.u16(m.channel_id) && r.u32(m.sequence) && r.u64(m.log_time) && r.u64(m.publish_time);
}

bool decode_chunk_header(const uint8_t* content, size_t size, ChunkHeader& h) {
    ByteReader r(content, size);
    if (!(r.u64(h.message_start_time) && r.u64(h.message_end_time) && r.u64(h.uncompressed_size) &&
          r.u32(h.uncompressed_crc) && r.str(h.compression) && r.u64(h.records_size))) {
        return false;
    }
    h.records_offset = r.pos();
    return true;
}

bool decode_statistics(const uint8_t* content, size_t size, Statistics& s) {
    ByteReader r(content, size);
    if (!(r.u64(s.message_count) && r.u16(s.schema_count) && r.u32(s.channel_count) &&
          r.u32(s.attachment_count) && r.u32(s.metadata_count) && r.u32(s.chunk_count) &&
          r.u64(s.message_start_time_ns) && r.u64(s.message_end_time_ns))) {
        return false;
    }
    uint32_t n;
    if (!r.u32(n) || n % 10 != 0 || r.remaining() < n) return false;
    for (uint32_t i = 0; i < n; i += 10) {
        uint16_t channel;
        uint64_t count;
        if (!r.u16(channel) || !r.u64(count)) return false;
        s.channel_message_counts[channel] = count;
    }
    return true;
}

}  // namespace df::mcap::detail
