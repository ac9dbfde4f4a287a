#pragma once
/// A Foxglove WebSocket server (protocol foxglove.websocket.v1,
/// https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md) that Foxglove Studio connects
/// to at ws://HOST:PORT. It advertises channels, takes subscribe/unsubscribe requests and streams
/// message data to the clients that subscribed. No DDS: the caller hands it encoded payloads.
///
/// One I/O thread per server does all socket work; publish() only queues, so a slow or stalled
/// client never slows the caller: beyond max_queued_bytes_per_client its new messages are dropped.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::foxglove {

/// The WebSocket subprotocol a client must offer; the server selects it.
inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

struct ServerOptions {
    /// Listens only on this address; "127.0.0.1" keeps the server local, "0.0.0.0" opens it to
    /// every interface.
    std::string address = "127.0.0.1";
    uint16_t port = 8765;  ///< 0 = any free port (port() tells which)
    /// Bytes of message data queued for one client; a message that would go beyond this (when
    /// something is queued already) is dropped for that client, never queued.
    size_t max_queued_bytes_per_client = 8u << 20;
    std::string name = "DetectFusion";  ///< serverInfo name shown by Foxglove Studio
};

struct ChannelInfo {
    std::string topic;             ///< e.g. "/df/foxglove/color"
    std::string encoding = "cdr";  ///< message encoding
    std::string schema_name;       ///< e.g. "foxglove::RawImage"
    std::string schema_encoding = "omgidl";
    std::string schema;  ///< schema text (IDL), sent as-is in advertise
};

class WebSocketServer {
  public:
    /// Binds address:port, listens and starts the I/O thread. Fails (naming address:port and the
    /// reason) when the address is not valid or not local, or the port is in use.
    static Result<std::unique_ptr<WebSocketServer>> start(const ServerOptions& options);
    /// Closes every client connection (a close frame where the client is not stalled), stops the
    /// I/O thread and joins it.
    ~WebSocketServer();
    WebSocketServer(const WebSocketServer&) = delete;
    WebSocketServer& operator=(const WebSocketServer&) = delete;

    /// Adds a channel and returns its id (1, 2, ...); it is advertised to connected clients now and
    /// to every client that connects later. Thread-safe.
    uint32_t add_channel(const ChannelInfo& channel);

    /// Queues `payload` (shared, not copied) for every client subscribed to `channel_id`, stamped
    /// `log_time_ns` (ns since the Unix epoch). Thread-safe and never waits for a client: a client
    /// whose queue is full drops the message (counted in dropped_messages()). A null payload or an
    /// unknown channel is ignored.
    void publish(uint32_t channel_id, uint64_t log_time_ns,
                 std::shared_ptr<const std::vector<uint8_t>> payload);

    /// Whether any client subscribes to `channel_id` now: lets the caller skip encoding work
    /// nobody wants.
    bool has_subscribers(uint32_t channel_id) const;
    /// How many clients subscribe to `channel_id` now.
    size_t subscriber_count(uint32_t channel_id) const;

    uint16_t port() const;        ///< the port listened on (the one chosen when options.port = 0)
    size_t client_count() const;  ///< clients past the WebSocket handshake, not yet closed
    uint64_t dropped_messages() const;  ///< message data dropped for full client queues, in total
    uint64_t sent_messages() const;     ///< message data written to client sockets, in total

  private:
    struct Impl;
    explicit WebSocketServer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace df::foxglove
