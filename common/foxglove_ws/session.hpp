#pragma once
/// One client connection (internal): the HTTP upgrade with the subprotocol check, the read loop
/// for subscribe/unsubscribe, and a send queue written by one async write at a time.
/// Socket work happens on the server's I/O thread; the queue_* and subscribes() calls are
/// thread-safe.
#include <array>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "foxglove_ws/protocol.hpp"

namespace df::foxglove {

class ServerState;

/// Whether a Sec-WebSocket-Protocol header value (a comma-separated list) offers `subprotocol`.
bool offers_subprotocol(const std::string& header_value, const std::string& subprotocol);

class Session : public std::enable_shared_from_this<Session> {
  public:
    enum class Queued { kQueued, kDropped, kNotSubscribed };

    Session(boost::asio::ip::tcp::socket socket, ServerState& state);

    /// Reads the upgrade request; refuses it (HTTP 400) unless it is a WebSocket upgrade offering
    /// kSubprotocol, else completes the handshake and opens the session in the server state.
    void run();
    /// Ends the connection with a close frame (going away), sent after any write in flight; the
    /// caller ends a client that never takes it with close_now(). I/O thread only.
    void close();
    /// Closes the socket without a close frame. I/O thread only.
    void close_now();

    /// Queues message data for `channel_id` when this client subscribes to it; drops it when
    /// `max_queued_bytes` of message data are queued already (one message is always let through
    /// to an empty queue). Never blocks on the socket.
    Queued queue_message_data(uint32_t channel_id, uint64_t log_time_ns,
                              const std::shared_ptr<const std::vector<uint8_t>>& payload,
                              size_t max_queued_bytes);
    /// Queues a JSON text message (never dropped: they are few and small).
    void queue_text(std::string json);
    bool subscribes(uint32_t channel_id) const;

  private:
    struct Outgoing {
        bool is_text = false;
        std::string text;
        std::array<uint8_t, kMessageDataHeaderSize> header{};
        std::shared_ptr<const std::vector<uint8_t>> payload;
        size_t data_bytes = 0;  // counted against the queue limit (message data only)
    };

    void on_request(boost::beast::error_code ec);
    void refuse(const std::string& why);
    void on_accept(boost::beast::error_code ec);
    void read_next();
    void on_read(boost::beast::error_code ec);
    void handle_text(const std::string& text);
    void subscribe(const ClientRequest& request);
    void unsubscribe(const ClientRequest& request);
    void warn_client(const std::string& message);
    /// Pushes under mutex_ (held by the caller) and starts the writer when idle.
    void push_locked(Outgoing message);
    void write_next();
    void on_write(boost::beast::error_code ec);
    void end(const char* why, boost::beast::error_code ec);

    ServerState& state_;
    const std::string peer_;  // "address:port" for log lines
    boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
    boost::asio::any_io_executor executor_;
    boost::beast::flat_buffer read_buffer_;
    boost::beast::http::request<boost::beast::http::string_body> request_;
    boost::beast::http::response<boost::beast::http::string_body> refusal_;
    bool ended_ = false;  // I/O thread only

    mutable std::mutex mutex_;    // guards the members below
    bool closed_ = false;         // no more queueing
    bool writing_ = false;        // an async write is in flight (or posted)
    std::deque<Outgoing> queue_;  // front = being written
    size_t queued_data_bytes_ = 0;
    bool dropping_ = false;  // the last message data was dropped (logged once per episode)
    std::map<uint32_t, uint32_t> channel_of_subscription_;
};

}  // namespace df::foxglove
