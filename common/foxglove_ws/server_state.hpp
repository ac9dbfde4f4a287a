#pragma once
/// What a server's clients share (internal): the channels, the clients past their handshake and
/// the counters. Thread-safe; publish() fans a message out to the subscribed clients' queues.
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "foxglove_ws/websocket_server.hpp"

namespace df::foxglove {

class Session;

class ServerState {
  public:
    ServerState(ServerOptions options, std::string session_id);

    const ServerOptions& options() const { return options_; }

    uint32_t add_channel(const ChannelInfo& channel);
    bool has_channel(uint32_t channel_id) const;

    /// A client finished its handshake: it gets serverInfo and the advertise of every channel
    /// (before any message data), then takes part in publish().
    void open_session(const std::shared_ptr<Session>& session);
    /// A client is gone; no-op when it was never opened or is closed already.
    void close_session(const Session* session);

    void publish(uint32_t channel_id, uint64_t log_time_ns,
                 const std::shared_ptr<const std::vector<uint8_t>>& payload);
    size_t subscriber_count(uint32_t channel_id) const;
    size_t client_count() const;

    void count_sent() { sent_.fetch_add(1, std::memory_order_relaxed); }
    uint64_t sent_messages() const { return sent_.load(std::memory_order_relaxed); }
    uint64_t dropped_messages() const { return dropped_.load(std::memory_order_relaxed); }

  private:
    const ServerOptions options_;
    const std::string session_id_;
    mutable std::mutex mutex_;  // guards channels_, next_channel_id_, open_; taken before a
                                // session's own mutex, never after
    std::map<uint32_t, ChannelInfo> channels_;
    uint32_t next_channel_id_ = 1;
    std::vector<std::shared_ptr<Session>> open_;
    std::atomic<uint64_t> sent_{0};
    std::atomic<uint64_t> dropped_{0};
};

}  // namespace df::foxglove
