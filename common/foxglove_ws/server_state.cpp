#include "foxglove_ws/server_state.hpp"

#include <algorithm>
#include <utility>

#include "foxglove_ws/protocol.hpp"
#include "foxglove_ws/session.hpp"

namespace df::foxglove {

ServerState::ServerState(ServerOptions options, std::string session_id)
    : options_(std::move(options)), session_id_(std::move(session_id)) {}

uint32_t ServerState::add_channel(const ChannelInfo& channel) {
    std::lock_guard<std::mutex> lock(mutex_);
    const uint32_t id = next_channel_id_++;
    channels_.emplace(id, channel);
    const std::string advertise = advertise_json({{id, channel}});
    for (const auto& session : open_) session->queue_text(advertise);
    return id;
}

bool ServerState::has_channel(uint32_t channel_id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return channels_.count(channel_id) > 0;
}

void ServerState::open_session(const std::shared_ptr<Session>& session) {
    std::lock_guard<std::mutex> lock(mutex_);
    session->queue_text(server_info_json(options_.name, session_id_));
    std::vector<std::pair<uint32_t, ChannelInfo>> channels(channels_.begin(), channels_.end());
    session->queue_text(advertise_json(channels));
    open_.push_back(session);
}

void ServerState::close_session(const Session* session) {
    std::lock_guard<std::mutex> lock(mutex_);
    open_.erase(std::remove_if(open_.begin(), open_.end(),
                               [session](const auto& s) { return s.get() == session; }),
                open_.end());
}

void ServerState::publish(uint32_t channel_id, uint64_t log_time_ns,
                          const std::shared_ptr<const std::vector<uint8_t>>& payload) {
    if (!payload) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (channels_.count(channel_id) == 0) return;
    for (const auto& session : open_) {
        const auto queued = session->queue_message_data(channel_id, log_time_ns, payload,
                                                        options_.max_queued_bytes_per_client);
        if (queued == Session::Queued::kDropped) dropped_.fetch_add(1, std::memory_order_relaxed);
    }
}

size_t ServerState::subscriber_count(uint32_t channel_id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return static_cast<size_t>(std::count_if(
        open_.begin(), open_.end(), [&](const auto& s) { return s->subscribes(channel_id); }));
}

size_t ServerState::client_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return open_.size();
}

}  // namespace df::foxglove
