#pragma once
/// Plain values shared by the MCAP writer and reader (see the MCAP specification, major version 0).
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace df::mcap {

/// A message schema, e.g. name "df::msg::RgbdFrame", encoding "omgidl", data = the IDL text.
struct Schema {
    uint16_t id = 0;  ///< unique in the file, never 0
    std::string name;
    std::string encoding;
    std::string data;  ///< raw schema bytes (text for omgidl)

    bool operator==(const Schema& o) const {
        return id == o.id && name == o.name && encoding == o.encoding && data == o.data;
    }
};

/// One stream of messages on a topic; schema_id 0 means "no schema".
struct Channel {
    uint16_t id = 0;
    uint16_t schema_id = 0;
    std::string topic;
    std::string message_encoding;  ///< e.g. "cdr" (bytes include the 4-byte encapsulation header)
    std::map<std::string, std::string> metadata;

    bool operator==(const Channel& o) const {
        return id == o.id && schema_id == o.schema_id && topic == o.topic &&
               message_encoding == o.message_encoding && metadata == o.metadata;
    }
};

/// One message as handed to Reader::for_each_message. `data` points into the reader's buffer
/// and is valid only during the callback: copy it to keep it.
struct Message {
    uint16_t channel_id = 0;
    uint32_t sequence = 0;
    uint64_t log_time_ns = 0;      ///< when the recorder received it
    uint64_t publish_time_ns = 0;  ///< when the publisher sent it
    const uint8_t* data = nullptr;
    size_t size = 0;
};

/// The file's Statistics record (written by our Writer in the summary section).
struct Statistics {
    uint64_t message_count = 0;
    uint16_t schema_count = 0;
    uint32_t channel_count = 0;
    uint32_t attachment_count = 0;
    uint32_t metadata_count = 0;
    uint32_t chunk_count = 0;
    uint64_t message_start_time_ns = 0;  ///< earliest log time, 0 when there are no messages
    uint64_t message_end_time_ns = 0;    ///< latest log time, 0 when there are no messages
    std::map<uint16_t, uint64_t> channel_message_counts;
};

}  // namespace df::mcap
