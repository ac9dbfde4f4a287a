#include "foxglove_ws/protocol.hpp"

#include <limits>
#include <nlohmann/json.hpp>

namespace df::foxglove {
namespace {

using nlohmann::json;

/// An id: a JSON integer in [0, 2^32).
bool to_id(const json& value, uint32_t* id) {
    if (!value.is_number_integer()) return false;
    if (value.is_number_unsigned()) {
        uint64_t v = value.get<uint64_t>();
        if (v > std::numeric_limits<uint32_t>::max()) return false;
        *id = static_cast<uint32_t>(v);
        return true;
    }
    int64_t v = value.get<int64_t>();
    if (v < 0 || v > std::numeric_limits<uint32_t>::max()) return false;
    *id = static_cast<uint32_t>(v);
    return true;
}

bool read_id(const json& object, const char* key, uint32_t* id) {
    auto it = object.find(key);
    return it != object.end() && to_id(*it, id);
}

/// Compact JSON text; invalid UTF-8 (in a topic, a schema or a quoted client field) is replaced,
/// never thrown.
std::string to_text(const json& j) {
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

ClientRequest invalid(std::string op, std::string why) {
    ClientRequest r;
    r.kind = ClientRequest::Kind::kInvalid;
    r.op = std::move(op);
    r.error = std::move(why);
    return r;
}

ClientRequest parse_subscribe(const json& message) {
    auto list = message.find("subscriptions");
    if (list == message.end() || !list->is_array()) {
        return invalid("subscribe", "subscribe needs an array \"subscriptions\"");
    }
    ClientRequest r;
    r.kind = ClientRequest::Kind::kSubscribe;
    r.op = "subscribe";
    for (const json& entry : *list) {
        uint32_t id = 0, channel_id = 0;
        if (!entry.is_object() || !read_id(entry, "id", &id) ||
            !read_id(entry, "channelId", &channel_id)) {
            return invalid("subscribe",
                           "subscribe: each subscription needs integer \"id\" and \"channelId\" "
                           "in [0, 2^32), got " +
                               to_text(entry));
        }
        r.subscriptions.emplace_back(id, channel_id);
    }
    return r;
}

ClientRequest parse_unsubscribe(const json& message) {
    auto list = message.find("subscriptionIds");
    if (list == message.end() || !list->is_array()) {
        return invalid("unsubscribe", "unsubscribe needs an array \"subscriptionIds\"");
    }
    ClientRequest r;
    r.kind = ClientRequest::Kind::kUnsubscribe;
    r.op = "unsubscribe";
    for (const json& entry : *list) {
        uint32_t id = 0;
        if (!to_id(entry, &id)) {
            return invalid(
                "unsubscribe",
                "unsubscribe: subscription ids are integers in [0, 2^32), got " + to_text(entry));
        }
        r.subscription_ids.push_back(id);
    }
    return r;
}

}  // namespace

std::string server_info_json(const std::string& name, const std::string& session_id) {
    json j = {{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()},
              {"sessionId", session_id}};
    return to_text(j);
}

std::string advertise_json(const std::vector<std::pair<uint32_t, ChannelInfo>>& channels) {
    json list = json::array();
    for (const auto& [id, c] : channels) {
        list.push_back({{"id", id},
                        {"topic", c.topic},
                        {"encoding", c.encoding},
                        {"schemaName", c.schema_name},
                        {"schema", c.schema},
                        {"schemaEncoding", c.schema_encoding}});
    }
    json j = {{"op", "advertise"}, {"channels", std::move(list)}};
    return to_text(j);
}

std::string status_json(StatusLevel level, const std::string& message) {
    json j = {{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}};
    return to_text(j);
}

std::array<uint8_t, kMessageDataHeaderSize> message_data_header(uint32_t subscription_id,
                                                                uint64_t log_time_ns) {
    std::array<uint8_t, kMessageDataHeaderSize> h{};
    h[0] = 0x01;
    for (int i = 0; i < 4; ++i) h[1 + i] = static_cast<uint8_t>(subscription_id >> (8 * i));
    for (int i = 0; i < 8; ++i) h[5 + i] = static_cast<uint8_t>(log_time_ns >> (8 * i));
    return h;
}

ClientRequest parse_client_request(std::string_view text) {
    json message = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (message.is_discarded()) return invalid("", "message is not valid JSON");
    if (!message.is_object()) return invalid("", "message is not a JSON object");
    auto op = message.find("op");
    if (op == message.end() || !op->is_string()) {
        return invalid("", "message has no string field \"op\"");
    }
    const std::string name = op->get<std::string>();
    if (name == "subscribe") return parse_subscribe(message);
    if (name == "unsubscribe") return parse_unsubscribe(message);
    ClientRequest r;
    r.kind = ClientRequest::Kind::kUnsupported;
    r.op = name;
    return r;
}

}  // namespace df::foxglove
