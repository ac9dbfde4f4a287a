#pragma once
/// The messages of the Foxglove WebSocket protocol v1 this server speaks, as pure functions:
/// JSON text the server sends, the binary Message Data header, and the client requests it reads
/// (https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "foxglove_ws/websocket_server.hpp"

namespace df::foxglove {

/// Status message levels of the protocol.
enum class StatusLevel { kInfo = 0, kWarning = 1, kError = 2 };

/// {"op":"serverInfo", name, capabilities: [], supportedEncodings: [], metadata: {}, sessionId}.
std::string server_info_json(const std::string& name, const std::string& session_id);
/// {"op":"advertise","channels":[{id, topic, encoding, schemaName, schema, schemaEncoding}...]}.
std::string advertise_json(const std::vector<std::pair<uint32_t, ChannelInfo>>& channels);
/// {"op":"status","level":L,"message":...}.
std::string status_json(StatusLevel level, const std::string& message);

/// Bytes before the payload of a binary Message Data frame: opcode 0x01, subscription id
/// (uint32 little-endian), log time in ns (uint64 little-endian).
inline constexpr size_t kMessageDataHeaderSize = 1 + 4 + 8;
std::array<uint8_t, kMessageDataHeaderSize> message_data_header(uint32_t subscription_id,
                                                                uint64_t log_time_ns);

/// One JSON text message from a client, checked field by field.
struct ClientRequest {
    enum class Kind { kSubscribe, kUnsubscribe, kUnsupported, kInvalid };
    Kind kind = Kind::kInvalid;
    std::string op;  ///< the "op" field, when there is one
    /// kSubscribe: (subscription id, channel id) pairs.
    std::vector<std::pair<uint32_t, uint32_t>> subscriptions;
    std::vector<uint32_t> subscription_ids;  ///< kUnsubscribe
    std::string error;  ///< kInvalid: what is wrong, for a status message to the client
};

/// Parses a client's text message. Never throws: malformed JSON, a missing "op" or fields of the
/// wrong type give kInvalid with a reason; an op this server does not handle gives kUnsupported.
ClientRequest parse_client_request(std::string_view text);

}  // namespace df::foxglove
