#pragma once
/// Writes MCAP files (https://mcap.dev/spec) that Foxglove Studio and @mcap/core can open:
/// messages in chunks (each followed by its MessageIndex records), then a summary section
/// (Schema, Channel, ChunkIndex, Statistics), SummaryOffset records and the Footer.
/// Memory use is bounded by one chunk (chunk_size_bytes, or one message when larger).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "mcap/mcap_records.hpp"
#include "mcap/mcap_types.hpp"

namespace df::mcap {

struct WriterOptions {
    enum class Compression { kNone, kZstd };

    std::string profile;                   ///< Header profile; "" = no well-known profile
    std::string library = "detectfusion";  ///< Header library (writer name/version)
    /// A chunk is closed once its uncompressed records reach this many bytes; a message larger
    /// than this gets a chunk of its own.
    uint64_t chunk_size_bytes = 4u << 20;
    Compression compression = Compression::kNone;
    int zstd_level = 1;  ///< used with kZstd; 1 is fast enough for live 30 Hz RGB-D
};

/// Writes one MCAP file. Not thread-safe. Closes the file (summary + footer) in the destructor
/// when close() was not called; call close() yourself to see its Status.
/// After the first failed file write every call returns that error.
class Writer {
  public:
    /// Creates (truncates) `path` and writes the magic and the Header record.
    static Result<std::unique_ptr<Writer>> open(const std::string& path,
                                                WriterOptions options = {});
    ~Writer();
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    /// Registers a schema, e.g. ("df::msg::RgbdFrame", "omgidl", idl_text). Returns its id
    /// (1, 2, ...); a schema identical to one already added returns that one's id.
    Result<uint16_t> add_schema(const std::string& name, const std::string& encoding,
                                const std::string& data);
    /// Registers a channel on `topic`; `schema_id` is 0 (no schema) or an id from add_schema.
    /// Returns its id (1, 2, ...).
    Result<uint16_t> add_channel(uint16_t schema_id, const std::string& topic,
                                 const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata = {});
    /// Appends one message; `data` (e.g. CDR bytes with encapsulation header) is copied.
    /// Times are ns since the Unix epoch; log time = when recorded, publish time = when sent.
    Status write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
                 uint64_t publish_time_ns, const uint8_t* data, size_t size);
    /// Writes the last chunk, DataEnd, summary, footer and magic, then closes the file.
    /// Calling it again returns the first call's result.
    Status close();

    const std::string& path() const { return path_; }
    uint64_t message_count() const { return message_count_; }
    /// Bytes written to the file so far (the current chunk is not counted until it is written).
    uint64_t bytes_written() const { return offset_; }

  private:
    struct ChunkIndex {
        uint64_t message_start_time = 0, message_end_time = 0;
        uint64_t chunk_offset = 0, chunk_length = 0;
        std::map<uint16_t, uint64_t> message_index_offsets;
        uint64_t message_index_length = 0;
        uint64_t compressed_size = 0, uncompressed_size = 0;
    };

    Writer(std::string path, WriterOptions options, std::FILE* file);
    Status check_writable() const;
    /// Writes bytes at the end of the file; until DataEnd they also feed the data section CRC.
    Status write_bytes(const uint8_t* data, size_t size);
    Status flush_chunk();
    Status write_message_indexes(ChunkIndex& index);
    std::vector<uint8_t> encode_summary(uint64_t summary_start) const;
    const char* compression_name() const;

    std::string path_;
    WriterOptions options_;
    std::FILE* file_;
    uint64_t offset_ = 0;
    detail::Crc32 data_crc_;  // running CRC-32 of the data section (magic through last record)
    bool data_section_ended_ = false;
    bool closed_ = false;
    Status failure_;  // first write error; sticky
    Status close_status_;

    std::map<uint16_t, Schema> schemas_;
    std::map<uint16_t, Channel> channels_;

    // The chunk being filled: uncompressed records and, per channel, (log time, offset) pairs.
    std::vector<uint8_t> chunk_records_;
    std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_message_index_;
    uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
    std::vector<uint8_t> compressed_;  // reused output buffer for zstd

    std::vector<ChunkIndex> chunk_indexes_;
    uint64_t message_count_ = 0;
    uint64_t start_time_ = 0, end_time_ = 0;
    std::map<uint16_t, uint64_t> channel_message_counts_;
};

}  // namespace df::mcap
