#pragma once
/// Reads MCAP files (https://mcap.dev/spec): ours and those of other writers, with chunks that
/// are uncompressed or zstd-compressed, and top-level Message records.
/// The file is read record by record (never whole): open() walks the top-level records and the
/// summary; for_each_message() then loads one chunk at a time (more only where chunks overlap
/// in time). Every malformed or truncated file gives an error naming the file and byte offset.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "mcap/mcap_types.hpp"

namespace df::mcap {

class Reader {
  public:
    /// Opens `path` and checks its structure: leading magic, Header, every top-level record's
    /// length, Footer and trailing magic, and the summary CRC. Fails for a truncated file
    /// (e.g. a recording that was never closed). Schemas and channels come from the summary,
    /// or, when the file has none, from the records of the data section and its chunks.
    static Result<std::unique_ptr<Reader>> open(const std::string& path);
    ~Reader();
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    const std::string& path() const { return path_; }
    const std::string& profile() const { return profile_; }
    const std::string& library() const { return library_; }
    const std::map<uint16_t, Schema>& schemas() const { return schemas_; }
    const std::map<uint16_t, Channel>& channels() const { return channels_; }
    /// The Statistics record, when the file has one.
    const std::optional<Statistics>& statistics() const { return statistics_; }

    /// Calls `fn` for every message in log-time order (ties: file order). `fn` returns false to
    /// stop early (the result is then ok). Chunk CRCs are checked. The Message's data pointer is
    /// valid only during the call.
    Status for_each_message(const std::function<bool(const Message&)>& fn);

  private:
    /// A chunk or a top-level Message record in the data section.
    struct DataUnit {
        uint64_t offset = 0;  ///< of the record's opcode
        uint64_t content_length = 0;
        uint64_t start_time = 0;  ///< earliest log time inside
        bool is_chunk = false;
    };
    struct LoadedRecords;
    struct Pending;

    Reader(std::string path, int fd, uint64_t size);
    Status read_at(uint64_t offset, size_t size, uint8_t* dst) const;
    Status read_record_content(uint64_t offset, uint64_t length, std::vector<uint8_t>& out) const;
    /// Walks the top-level records from the Header to the Footer (see open()).
    Status scan();
    /// One top-level record other than the Footer, whose length scan() has checked.
    Status scan_record(uint64_t offset, uint8_t op, uint64_t length, bool& in_data_section);
    Status scan_chunk(uint64_t offset, uint64_t length);
    /// Footer, closing magic and summary CRC.
    Status check_footer(uint64_t footer_offset, uint64_t content_length);
    /// Registers a schema/channel; false when one with the same id but other content exists.
    bool add_schema(const Schema& s);
    bool add_channel(const Channel& c);
    /// Loads a chunk's (uncompressed) records, checking compression, size and CRC.
    Status load_chunk(const DataUnit& unit, LoadedRecords& loaded) const;
    /// Walks the records inside a loaded chunk: registers schemas/channels, collects messages.
    Status walk_chunk(const DataUnit& unit, const LoadedRecords& loaded,
                      std::vector<Pending>* messages);
    /// A kIoError "MCAP file '<path>', byte <offset>: <what>".
    Status fail(uint64_t offset, const std::string& what) const;

    std::string path_;
    int fd_ = -1;
    uint64_t size_ = 0;
    std::string profile_, library_;
    std::map<uint16_t, Schema> schemas_;
    std::map<uint16_t, Channel> channels_;
    std::optional<Statistics> statistics_;
    std::vector<DataUnit> units_;  // in file order
    bool summary_has_channels_ = false;
};

}  // namespace df::mcap
