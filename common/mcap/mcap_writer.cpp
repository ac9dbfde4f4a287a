#include "mcap/mcap_writer.hpp"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/log.hpp"

namespace df::mcap {

using detail::ByteWriter;
using detail::Op;

Result<std::unique_ptr<Writer>> Writer::open(const std::string& path, WriterOptions options) {
    if (options.chunk_size_bytes == 0) {
        return error(StatusCode::kInvalidArgument,
                     "MCAP writer for '" + path + "': chunk_size_bytes must be > 0");
    }
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (file == nullptr) {
        const int err = errno;
        return error(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                     "cannot create MCAP file '" + path + "': " + std::strerror(err));
    }
    std::unique_ptr<Writer> writer(new Writer(path, std::move(options), file));

    std::vector<uint8_t> head;
    ByteWriter w(head);
    w.bytes(detail::kMagic, sizeof(detail::kMagic));
    const size_t start = w.begin_record(Op::kHeader);
    w.str(writer->options_.profile);
    w.str(writer->options_.library);
    w.end_record(start);
    DF_RETURN_IF_ERROR(writer->write_bytes(head.data(), head.size()));
    return writer;
}

Writer::Writer(std::string path, WriterOptions options, std::FILE* file)
    : path_(std::move(path)), options_(std::move(options)), file_(file) {}

Writer::~Writer() {
    if (closed_) return;
    const Status status = close();
    if (!status.is_ok())
        log::error("MCAP writer: closing on destruction failed: ", status.to_string());
}

Status Writer::check_writable() const {
    if (!failure_.is_ok()) return failure_;
    if (closed_) return error(StatusCode::kInvalidArgument, "MCAP file '" + path_ + "' is closed");
    return Status::ok();
}

Status Writer::write_bytes(const uint8_t* data, size_t size) {
    if (!failure_.is_ok()) return failure_;
    if (size > 0 && std::fwrite(data, 1, size, file_) != size) {
        failure_ =
            error(StatusCode::kIoError, "writing MCAP file '" + path_ + "' failed at byte " +
                                            std::to_string(offset_) + ": " + std::strerror(errno));
        return failure_;
    }
    if (!data_section_ended_) data_crc_.update(data, size);
    offset_ += size;
    return Status::ok();
}

Result<uint16_t> Writer::add_schema(const std::string& name, const std::string& encoding,
                                    const std::string& data) {
    DF_RETURN_IF_ERROR(check_writable());
    for (const auto& [id, s] : schemas_) {
        if (s.name == name && s.encoding == encoding && s.data == data) return id;
    }
    if (schemas_.size() >= 0xFFFF) {
        return error(StatusCode::kResourceExhausted, "MCAP file '" + path_ + "': 65535 schemas");
    }
    const Schema schema{uint16_t(schemas_.size() + 1), name, encoding, data};
    schemas_[schema.id] = schema;
    // Goes into the current chunk, before any message that can use it; a chunk that ends up with
    // no messages is written as top-level records instead.
    detail::encode_schema(chunk_records_, schema);
    return schema.id;
}

Result<uint16_t> Writer::add_channel(uint16_t schema_id, const std::string& topic,
                                     const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
    DF_RETURN_IF_ERROR(check_writable());
    if (schema_id != 0 && schemas_.count(schema_id) == 0) {
        return error(StatusCode::kInvalidArgument,
                     "MCAP file '" + path_ + "': channel '" + topic + "' names schema id " +
                         std::to_string(schema_id) + ", which add_schema did not return");
    }
    if (channels_.size() >= 0xFFFF) {
        return error(StatusCode::kResourceExhausted, "MCAP file '" + path_ + "': 65535 channels");
    }
    const Channel channel{uint16_t(channels_.size() + 1), schema_id, topic, message_encoding,
                          metadata};
    channels_[channel.id] = channel;
    detail::encode_channel(chunk_records_, channel);
    return channel.id;
}

Status Writer::write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
                     uint64_t publish_time_ns, const uint8_t* data, size_t size) {
    DF_RETURN_IF_ERROR(check_writable());
    if (channels_.count(channel_id) == 0) {
        return error(StatusCode::kInvalidArgument,
                     "MCAP file '" + path_ + "': message on channel id " +
                         std::to_string(channel_id) + ", which add_channel did not return");
    }
    const uint64_t record_bytes = detail::kRecordPrefixBytes + detail::kMessageFieldsBytes + size;
    if (!chunk_message_index_.empty() &&
        chunk_records_.size() + record_bytes > options_.chunk_size_bytes) {
        DF_RETURN_IF_ERROR(flush_chunk());
    }

    const uint64_t offset_in_chunk = chunk_records_.size();
    detail::encode_message_prefix(chunk_records_,
                                  {channel_id, sequence, log_time_ns, publish_time_ns}, size);
    if (size > 0) chunk_records_.insert(chunk_records_.end(), data, data + size);
    if (chunk_message_index_.empty()) {
        chunk_start_time_ = chunk_end_time_ = log_time_ns;
    } else {
        chunk_start_time_ = std::min(chunk_start_time_, log_time_ns);
        chunk_end_time_ = std::max(chunk_end_time_, log_time_ns);
    }
    chunk_message_index_[channel_id].emplace_back(log_time_ns, offset_in_chunk);

    if (message_count_ == 0) {
        start_time_ = end_time_ = log_time_ns;
    } else {
        start_time_ = std::min(start_time_, log_time_ns);
        end_time_ = std::max(end_time_, log_time_ns);
    }
    ++message_count_;
    ++channel_message_counts_[channel_id];

    if (chunk_records_.size() >= options_.chunk_size_bytes) return flush_chunk();
    return Status::ok();
}

const char* Writer::compression_name() const {
    return options_.compression == WriterOptions::Compression::kZstd ? "zstd" : "";
}

Status Writer::flush_chunk() {
    if (chunk_records_.empty()) return Status::ok();
    if (chunk_message_index_.empty()) {  // only Schema/Channel records: no chunk needed
        DF_RETURN_IF_ERROR(write_bytes(chunk_records_.data(), chunk_records_.size()));
        chunk_records_.clear();
        return Status::ok();
    }

    const uint64_t uncompressed_size = chunk_records_.size();
    const uint32_t uncompressed_crc = detail::crc32(chunk_records_.data(), chunk_records_.size());
    const uint8_t* records = chunk_records_.data();
    uint64_t records_size = uncompressed_size;
    if (options_.compression == WriterOptions::Compression::kZstd) {
        compressed_.resize(ZSTD_compressBound(chunk_records_.size()));
        const size_t n =
            ZSTD_compress(compressed_.data(), compressed_.size(), chunk_records_.data(),
                          chunk_records_.size(), options_.zstd_level);
        if (ZSTD_isError(n)) {
            failure_ = error(
                StatusCode::kInternal,
                "MCAP file '" + path_ + "': zstd compression failed: " + ZSTD_getErrorName(n));
            return failure_;
        }
        records = compressed_.data();
        records_size = n;
    }

    ChunkIndex index;
    index.message_start_time = chunk_start_time_;
    index.message_end_time = chunk_end_time_;
    index.chunk_offset = offset_;
    index.compressed_size = records_size;
    index.uncompressed_size = uncompressed_size;

    const std::string compression = compression_name();
    std::vector<uint8_t> head;
    ByteWriter w(head);
    w.u8(uint8_t(Op::kChunk));
    w.u64(8 + 8 + 8 + 4 + 4 + compression.size() + 8 + records_size);
    w.u64(chunk_start_time_);
    w.u64(chunk_end_time_);
    w.u64(uncompressed_size);
    w.u32(uncompressed_crc);
    w.str(compression);
    w.u64(records_size);
    DF_RETURN_IF_ERROR(write_bytes(head.data(), head.size()));
    DF_RETURN_IF_ERROR(write_bytes(records, records_size));
    index.chunk_length = offset_ - index.chunk_offset;

    DF_RETURN_IF_ERROR(write_message_indexes(index));
    chunk_indexes_.push_back(std::move(index));
    chunk_records_.clear();
    chunk_message_index_.clear();
    return Status::ok();
}

Status Writer::write_message_indexes(ChunkIndex& index) {
    std::vector<uint8_t> out;
    ByteWriter w(out);
    const uint64_t first = offset_;
    for (const auto& [channel_id, entries] : chunk_message_index_) {
        index.message_index_offsets[channel_id] = first + out.size();
        const size_t start = w.begin_record(Op::kMessageIndex);
        w.u16(channel_id);
        const size_t array = w.begin_u32_length();
        for (const auto& [log_time, offset] : entries) {
            w.u64(log_time);
            w.u64(offset);
        }
        w.end_u32_length(array);
        w.end_record(start);
    }
    index.message_index_length = out.size();
    DF_RETURN_IF_ERROR(write_bytes(out.data(), out.size()));
    return Status::ok();
}

std::vector<uint8_t> Writer::encode_summary(uint64_t summary_start) const {
    std::vector<uint8_t> out;
    ByteWriter w(out);
    struct Group {
        Op op;
        uint64_t start, length;
    };
    std::vector<Group> groups;
    const auto group = [&](Op op, const auto& write_records) {
        const size_t begin = out.size();
        write_records();
        if (out.size() > begin) groups.push_back({op, summary_start + begin, out.size() - begin});
    };

    group(Op::kSchema, [&] {
        for (const auto& [id, s] : schemas_) detail::encode_schema(out, s);
    });
    group(Op::kChannel, [&] {
        for (const auto& [id, c] : channels_) detail::encode_channel(out, c);
    });
    group(Op::kChunkIndex, [&] {
        for (const ChunkIndex& c : chunk_indexes_) {
            const size_t start = w.begin_record(Op::kChunkIndex);
            w.u64(c.message_start_time);
            w.u64(c.message_end_time);
            w.u64(c.chunk_offset);
            w.u64(c.chunk_length);
            const size_t map = w.begin_u32_length();
            for (const auto& [channel_id, offset] : c.message_index_offsets) {
                w.u16(channel_id);
                w.u64(offset);
            }
            w.end_u32_length(map);
            w.u64(c.message_index_length);
            w.str(compression_name());
            w.u64(c.compressed_size);
            w.u64(c.uncompressed_size);
            w.end_record(start);
        }
    });
    group(Op::kStatistics, [&] {
        const size_t start = w.begin_record(Op::kStatistics);
        w.u64(message_count_);
        w.u16(uint16_t(schemas_.size()));
        w.u32(uint32_t(channels_.size()));
        w.u32(0);  // attachments
        w.u32(0);  // metadata
        w.u32(uint32_t(chunk_indexes_.size()));
        w.u64(start_time_);
        w.u64(end_time_);
        const size_t map = w.begin_u32_length();
        for (const auto& [channel_id, count] : channel_message_counts_) {
            w.u16(channel_id);
            w.u64(count);
        }
        w.end_u32_length(map);
        w.end_record(start);
    });

    const uint64_t summary_offset_start = summary_start + out.size();
    for (const Group& g : groups) {
        const size_t start = w.begin_record(Op::kSummaryOffset);
        w.u8(uint8_t(g.op));
        w.u64(g.start);
        w.u64(g.length);
        w.end_record(start);
    }
    w.u8(uint8_t(Op::kFooter));
    w.u64(detail::kFooterBytes);
    w.u64(summary_start);
    w.u64(summary_offset_start);
    // The summary CRC covers the summary and summary offset sections and the footer up to here.
    w.u32(detail::crc32(out.data(), out.size()));
    w.bytes(detail::kMagic, sizeof(detail::kMagic));
    return out;
}

Status Writer::close() {
    if (closed_) return close_status_;
    Status status = flush_chunk();
    if (status.is_ok()) {
        std::vector<uint8_t> data_end;
        ByteWriter w(data_end);
        const size_t start = w.begin_record(Op::kDataEnd);
        w.u32(data_crc_.value());
        w.end_record(start);
        data_section_ended_ = true;
        status = write_bytes(data_end.data(), data_end.size());
    }
    if (status.is_ok()) {
        const std::vector<uint8_t> summary = encode_summary(offset_);
        status = write_bytes(summary.data(), summary.size());
    }
    closed_ = true;
    if (std::fclose(file_) != 0 && status.is_ok()) {
        status = error(StatusCode::kIoError,
                       "closing MCAP file '" + path_ + "' failed: " + std::strerror(errno));
    }
    file_ = nullptr;
    close_status_ = status;
    return status;
}

}  // namespace df::mcap
