#include "mcap/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <queue>

#include "mcap/mcap_records.hpp"

namespace df::mcap {

using detail::Op;
using detail::op_name;

namespace {

// Guards against allocating absurd sizes read from a corrupt length field.
constexpr uint64_t kMaxSmallRecordBytes = 256ull << 20;  // Header, Schema, Channel, Statistics
constexpr uint64_t kMaxChunkBytes = 4ull << 30;

uint64_t le64(const uint8_t* p) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(p[i]) << (8 * i);
    return v;
}

uint32_t le32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

std::string str(uint64_t v) { return std::to_string(v); }

}  // namespace

/// Uncompressed chunk records (or one top-level Message's content) inside a shared buffer, so
/// that pending messages keep it alive.
struct Reader::LoadedRecords {
    std::shared_ptr<const std::vector<uint8_t>> buffer;
    size_t begin = 0;
    size_t size = 0;
};

/// A message waiting in the log-time merge.
struct Reader::Pending {
    uint64_t ordinal = 0;  // (unit index << 32 | index in unit): breaks log-time ties in file order
    uint64_t source_offset = 0;  // file offset of its chunk or record, for errors
    detail::MessageFields fields;
    std::shared_ptr<const std::vector<uint8_t>> buffer;
    size_t data_offset = 0;
    size_t data_size = 0;
};

Result<std::unique_ptr<Reader>> Reader::open(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        return error(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                     "cannot open MCAP file '" + path + "': " + std::strerror(err));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int err = errno;
        ::close(fd);
        return error(StatusCode::kIoError,
                     "cannot stat MCAP file '" + path + "': " + std::strerror(err));
    }
    std::unique_ptr<Reader> reader(new Reader(path, fd, uint64_t(st.st_size)));
    DF_RETURN_IF_ERROR(reader->scan());
    return reader;
}

Reader::Reader(std::string path, int fd, uint64_t size)
    : path_(std::move(path)), fd_(fd), size_(size) {}

Reader::~Reader() {
    if (fd_ >= 0) ::close(fd_);
}

Status Reader::fail(uint64_t offset, const std::string& what) const {
    return error(StatusCode::kIoError,
                 "MCAP file '" + path_ + "', byte " + str(offset) + ": " + what);
}

Status Reader::read_at(uint64_t offset, size_t size, uint8_t* dst) const {
    size_t done = 0;
    while (done < size) {
        const ssize_t n = ::pread(fd_, dst + done, size - done, off_t(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            return fail(offset + done, n == 0
                                           ? std::string("unexpected end of file")
                                           : std::string("read failed: ") + std::strerror(errno));
        }
        done += size_t(n);
    }
    return Status::ok();
}

Status Reader::read_record_content(uint64_t offset, uint64_t length,
                                   std::vector<uint8_t>& out) const {
    out.resize(length);
    return read_at(offset, length, out.data());
}

bool Reader::add_schema(const Schema& s) {
    if (s.id == 0) return true;  // invalid per spec: ignored
    const auto [it, inserted] = schemas_.emplace(s.id, s);
    return inserted || it->second == s;
}

bool Reader::add_channel(const Channel& c) {
    const auto [it, inserted] = channels_.emplace(c.id, c);
    return inserted || it->second == c;
}

Status Reader::scan() {
    uint8_t magic[8];
    if (size_ < sizeof(magic)) {
        return fail(0, "file has " + str(size_) + " bytes, too short for the 8 MCAP magic bytes");
    }
    DF_RETURN_IF_ERROR(read_at(0, sizeof(magic), magic));
    if (std::memcmp(magic, detail::kMagic, sizeof(magic)) != 0) {
        return fail(0, "not an MCAP file (no MCAP magic bytes at the start)");
    }

    bool in_data_section = true;
    for (uint64_t pos = sizeof(magic);;) {
        if (pos == size_) {
            return fail(pos,
                        "file ends without a Footer record (truncated, or a recording that "
                        "was not closed)");
        }
        if (size_ - pos < detail::kRecordPrefixBytes) {
            return fail(pos, "truncated record: 9 bytes of opcode and length needed, " +
                                 str(size_ - pos) + " left in the file");
        }
        uint8_t prefix[detail::kRecordPrefixBytes];
        DF_RETURN_IF_ERROR(read_at(pos, sizeof(prefix), prefix));
        const uint8_t op = prefix[0];
        const uint64_t length = le64(prefix + 1);
        const uint64_t at_content = pos + detail::kRecordPrefixBytes;
        if (length > size_ - at_content) {
            return fail(pos, op_name(op) + " record claims " + str(length) + " bytes but only " +
                                 str(size_ - at_content) +
                                 " are left in the file (truncated or corrupt)");
        }
        const bool first = pos == sizeof(magic);
        if (first != (op == uint8_t(Op::kHeader))) {
            return fail(pos, first ? "expected a Header record, found " + op_name(op)
                                   : std::string("a second Header record"));
        }
        if (op == uint8_t(Op::kFooter)) {
            DF_RETURN_IF_ERROR(check_footer(pos, length));
            break;
        }
        DF_RETURN_IF_ERROR(scan_record(pos, op, length, in_data_section));
        pos = at_content + length;
    }

    if (!summary_has_channels_) {  // no summary to trust: collect schemas/channels from chunks
        for (const DataUnit& unit : units_) {
            if (!unit.is_chunk) continue;
            LoadedRecords loaded;
            DF_RETURN_IF_ERROR(load_chunk(unit, loaded));
            DF_RETURN_IF_ERROR(walk_chunk(unit, loaded, nullptr));
        }
    }
    return Status::ok();
}

Status Reader::scan_record(uint64_t pos, uint8_t op, uint64_t length, bool& in_data_section) {
    const uint64_t at_content = pos + detail::kRecordPrefixBytes;
    std::vector<uint8_t> content;
    if (op == uint8_t(Op::kHeader) || op == uint8_t(Op::kSchema) || op == uint8_t(Op::kChannel) ||
        op == uint8_t(Op::kStatistics)) {
        if (length > kMaxSmallRecordBytes) {
            return fail(pos, op_name(op) + " record of " + str(length) + " bytes is implausible");
        }
        DF_RETURN_IF_ERROR(read_record_content(at_content, length, content));
    }
    switch (Op(op)) {
        case Op::kHeader: {
            detail::ByteReader r(content.data(), content.size());
            if (!r.str(profile_) || !r.str(library_)) return fail(pos, "malformed Header record");
            return Status::ok();
        }
        case Op::kSchema: {
            Schema s;
            if (!detail::decode_schema(content.data(), content.size(), s)) {
                return fail(pos, "malformed Schema record");
            }
            if (!add_schema(s))
                return fail(pos, "Schema id " + str(s.id) + " redefined differently");
            return Status::ok();
        }
        case Op::kChannel: {
            Channel c;
            if (!detail::decode_channel(content.data(), content.size(), c)) {
                return fail(pos, "malformed Channel record");
            }
            if (!add_channel(c))
                return fail(pos, "Channel id " + str(c.id) + " redefined differently");
            summary_has_channels_ = summary_has_channels_ || !in_data_section;
            return Status::ok();
        }
        case Op::kMessage: {
            if (!in_data_section) return fail(pos, "Message record after DataEnd");
            uint8_t fields[detail::kMessageFieldsBytes];
            if (length < sizeof(fields)) return fail(pos, "malformed Message record (too short)");
            DF_RETURN_IF_ERROR(read_at(at_content, sizeof(fields), fields));
            detail::MessageFields m;
            detail::decode_message_fields(fields, sizeof(fields), m);
            units_.push_back({pos, length, m.log_time, false});
            return Status::ok();
        }
        case Op::kChunk:
            if (!in_data_section) return fail(pos, "Chunk record after DataEnd");
            return scan_chunk(pos, length);
        case Op::kDataEnd:
            in_data_section = false;
            return Status::ok();
        case Op::kStatistics: {
            Statistics s;
            if (!detail::decode_statistics(content.data(), content.size(), s)) {
                return fail(pos, "malformed Statistics record");
            }
            statistics_ = s;
            return Status::ok();
        }
        default:  // indexes, attachments, metadata, summary offsets, unknown: not needed
            return Status::ok();
    }
}

Status Reader::scan_chunk(uint64_t pos, uint64_t length) {
    // Fixed fields (28 bytes), compression string length (4), the string, records length (8).
    const uint64_t at_content = pos + detail::kRecordPrefixBytes;
    uint8_t fixed[32];
    if (length < sizeof(fixed) + 8) return fail(pos, "malformed Chunk record (too short)");
    DF_RETURN_IF_ERROR(read_at(at_content, sizeof(fixed), fixed));
    const uint64_t head_size = sizeof(fixed) + le32(fixed + 28) + 8;
    if (head_size > length)
        return fail(pos, "malformed Chunk record (its fields run past its end)");
    std::vector<uint8_t> head(head_size);
    DF_RETURN_IF_ERROR(read_at(at_content, head.size(), head.data()));
    detail::ChunkHeader h;
    if (!detail::decode_chunk_header(head.data(), head.size(), h) ||
        h.records_size > length - h.records_offset) {
        return fail(pos, "malformed Chunk record (its records run past its end)");
    }
    units_.push_back({pos, length, h.message_start_time, true});
    return Status::ok();
}

Status Reader::check_footer(uint64_t footer_offset, uint64_t content_length) {
    if (content_length != detail::kFooterBytes) {
        return fail(footer_offset,
                    "Footer record has " + str(content_length) + " bytes, 20 expected");
    }
    const uint64_t end = footer_offset + detail::kRecordPrefixBytes + detail::kFooterBytes;
    uint8_t magic[8];
    if (size_ - end != sizeof(magic)) {
        return fail(end, "expected the 8 closing magic bytes after the Footer, found " +
                             str(size_ - end) + " bytes");
    }
    DF_RETURN_IF_ERROR(read_at(end, sizeof(magic), magic));
    if (std::memcmp(magic, detail::kMagic, sizeof(magic)) != 0) {
        return fail(end, "bad closing magic bytes");
    }
    uint8_t fields[detail::kFooterBytes];
    DF_RETURN_IF_ERROR(read_at(footer_offset + detail::kRecordPrefixBytes, sizeof(fields), fields));
    const uint64_t summary_start = le64(fields);
    const uint64_t summary_offset_start = le64(fields + 8);
    const uint32_t summary_crc = le32(fields + 16);
    if (summary_start > footer_offset || summary_offset_start > footer_offset ||
        (summary_offset_start != 0 && summary_offset_start < summary_start)) {
        return fail(footer_offset, "Footer points outside the summary (summary_start " +
                                       str(summary_start) + ", summary_offset_start " +
                                       str(summary_offset_start) + ")");
    }
    if (summary_crc != 0 && summary_start != 0) {
        // Summary and summary offset sections, then the Footer up to (not including) its CRC.
        const uint64_t crc_end = footer_offset + detail::kRecordPrefixBytes + 16;
        detail::Crc32 crc;
        std::vector<uint8_t> block(std::min<uint64_t>(1 << 20, crc_end - summary_start));
        for (uint64_t p = summary_start; p < crc_end;) {
            const size_t n = size_t(std::min<uint64_t>(block.size(), crc_end - p));
            DF_RETURN_IF_ERROR(read_at(p, n, block.data()));
            crc.update(block.data(), n);
            p += n;
        }
        if (crc.value() != summary_crc) {
            return fail(summary_start, "summary CRC mismatch (computed " + str(crc.value()) +
                                           ", Footer says " + str(summary_crc) + ")");
        }
    }
    return Status::ok();
}

Status Reader::load_chunk(const DataUnit& unit, LoadedRecords& loaded) const {
    if (unit.content_length > kMaxChunkBytes) {
        return fail(unit.offset,
                    "Chunk record of " + str(unit.content_length) + " bytes is implausible");
    }
    auto content = std::make_shared<std::vector<uint8_t>>();
    DF_RETURN_IF_ERROR(read_record_content(unit.offset + detail::kRecordPrefixBytes,
                                           unit.content_length, *content));
    detail::ChunkHeader h;
    detail::decode_chunk_header(content->data(), content->size(), h);  // checked by scan()
    const uint8_t* records = content->data() + h.records_offset;

    if (h.compression.empty()) {
        if (h.records_size != h.uncompressed_size) {
            return fail(unit.offset, "uncompressed chunk holds " + str(h.records_size) +
                                         " bytes of records but says " + str(h.uncompressed_size));
        }
        loaded = {content, h.records_offset, size_t(h.records_size)};
    } else if (h.compression == "zstd") {
        if (h.uncompressed_size > kMaxChunkBytes) {
            return fail(unit.offset,
                        "chunk uncompressed size " + str(h.uncompressed_size) + " is implausible");
        }
        // A zstd block decompresses to at most 128 KiB and takes at least 3 bytes, so the
        // compressed bytes bound the size: a chunk claiming more is refused before its buffer is
        // allocated (found by fuzz_mcap: 1 KiB claiming 4 GiB).
        const uint64_t zstd_bound = (h.records_size / 3 + 1) * (128ull << 10);
        if (h.uncompressed_size > zstd_bound) {
            return fail(unit.offset, "zstd chunk of " + str(h.records_size) +
                                         " compressed bytes cannot hold the " +
                                         str(h.uncompressed_size) + " bytes it says");
        }
        const unsigned long long frame_size = ZSTD_getFrameContentSize(records, h.records_size);
        if (frame_size == ZSTD_CONTENTSIZE_ERROR) {
            return fail(unit.offset, "zstd chunk does not start with a zstd frame");
        }
        if (frame_size != ZSTD_CONTENTSIZE_UNKNOWN && frame_size != h.uncompressed_size) {
            return fail(unit.offset, "zstd frame holds " + str(frame_size) +
                                         " bytes but chunk says " + str(h.uncompressed_size));
        }
        auto out = std::make_shared<std::vector<uint8_t>>(h.uncompressed_size);
        const size_t n = ZSTD_decompress(out->data(), out->size(), records, h.records_size);
        if (ZSTD_isError(n)) {
            return fail(unit.offset,
                        std::string("zstd chunk does not decompress: ") + ZSTD_getErrorName(n));
        }
        if (n != h.uncompressed_size) {
            return fail(unit.offset, "zstd chunk decompresses to " + str(n) + " bytes, " +
                                         str(h.uncompressed_size) + " expected");
        }
        loaded = {out, 0, n};
    } else {
        return fail(unit.offset, "chunk compression '" + h.compression +
                                     "' is not supported (only zstd or none)");
    }
    if (h.uncompressed_crc != 0) {
        const uint32_t crc = detail::crc32(loaded.buffer->data() + loaded.begin, loaded.size);
        if (crc != h.uncompressed_crc) {
            return fail(unit.offset, "chunk CRC mismatch (computed " + str(crc) + ", chunk says " +
                                         str(h.uncompressed_crc) + ")");
        }
    }
    return Status::ok();
}

Status Reader::walk_chunk(const DataUnit& unit, const LoadedRecords& loaded,
                          std::vector<Pending>* messages) {
    const uint8_t* base = loaded.buffer->data() + loaded.begin;
    const size_t n = loaded.size;
    for (size_t p = 0; p < n;) {
        const auto bad = [&](const std::string& what) {
            return fail(unit.offset,
                        "chunk record at byte " + str(p) + " of its uncompressed records: " + what);
        };
        if (n - p < detail::kRecordPrefixBytes) return bad("truncated record header");
        const uint8_t op = base[p];
        const uint64_t length = le64(base + p + 1);
        const size_t at_content = p + detail::kRecordPrefixBytes;
        if (length > n - at_content) {
            return bad(op_name(op) + " record claims " + str(length) + " bytes, " +
                       str(n - at_content) + " are left in the chunk");
        }
        const uint8_t* content = base + at_content;
        if (op == uint8_t(Op::kSchema)) {
            Schema s;
            if (!detail::decode_schema(content, length, s)) return bad("malformed Schema record");
            if (!add_schema(s)) return bad("Schema id " + str(s.id) + " redefined differently");
        } else if (op == uint8_t(Op::kChannel)) {
            Channel c;
            if (!detail::decode_channel(content, length, c)) return bad("malformed Channel record");
            if (!add_channel(c)) return bad("Channel id " + str(c.id) + " redefined differently");
        } else if (op == uint8_t(Op::kMessage) && messages != nullptr) {
            Pending m;
            if (!detail::decode_message_fields(content, length, m.fields)) {
                return bad("malformed Message record (too short)");
            }
            m.source_offset = unit.offset;
            m.buffer = loaded.buffer;
            m.data_offset = loaded.begin + at_content + detail::kMessageFieldsBytes;
            m.data_size = length - detail::kMessageFieldsBytes;
            messages->push_back(std::move(m));
        }
        p = at_content + length;
    }
    return Status::ok();
}

Status Reader::for_each_message(const std::function<bool(const Message&)>& fn) {
    std::vector<size_t> order(units_.size());  // indexes into units_ (file order)
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return units_[a].start_time < units_[b].start_time;
    });

    // k-way merge: a unit is loaded once no pending message is earlier than its start time, so
    // only chunks that overlap in time are held at once.
    const auto later = [](const Pending& a, const Pending& b) {
        if (a.fields.log_time != b.fields.log_time) return a.fields.log_time > b.fields.log_time;
        return a.ordinal > b.ordinal;
    };
    std::priority_queue<Pending, std::vector<Pending>, decltype(later)> heap(later);
    std::vector<Pending> batch;
    size_t next = 0;
    for (;;) {
        while (next < order.size() &&
               (heap.empty() || units_[order[next]].start_time <= heap.top().fields.log_time)) {
            const size_t unit_index = order[next++];
            const DataUnit& unit = units_[unit_index];
            batch.clear();
            LoadedRecords loaded;
            if (unit.is_chunk) {
                DF_RETURN_IF_ERROR(load_chunk(unit, loaded));
                DF_RETURN_IF_ERROR(walk_chunk(unit, loaded, &batch));
            } else {
                auto content = std::make_shared<std::vector<uint8_t>>();
                DF_RETURN_IF_ERROR(read_record_content(unit.offset + detail::kRecordPrefixBytes,
                                                       unit.content_length, *content));
                Pending m;
                detail::decode_message_fields(content->data(), content->size(), m.fields);
                m.source_offset = unit.offset;
                m.buffer = content;
                m.data_offset = detail::kMessageFieldsBytes;
                m.data_size = content->size() - detail::kMessageFieldsBytes;
                batch.push_back(std::move(m));
            }
            for (size_t i = 0; i < batch.size(); ++i) {
                Pending& m = batch[i];
                m.ordinal = (uint64_t(unit_index) << 32) | i;
                heap.push(std::move(m));
            }
        }
        if (heap.empty()) return Status::ok();
        const Pending m = heap.top();
        heap.pop();
        if (channels_.count(m.fields.channel_id) == 0) {
            return fail(m.source_offset, "message on channel id " + str(m.fields.channel_id) +
                                             ", which no Channel record defines");
        }
        const Message message{m.fields.channel_id,
                              m.fields.sequence,
                              m.fields.log_time,
                              m.fields.publish_time,
                              m.buffer->data() + m.data_offset,
                              m.data_size};
        if (!fn(message)) return Status::ok();
    }
}

}  // namespace df::mcap
