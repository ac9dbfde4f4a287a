#include "foxglove_ws/session.hpp"

#include <boost/asio/post.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <chrono>
#include <utility>

#include "core/log.hpp"
#include "foxglove_ws/server_state.hpp"

namespace df::foxglove {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;

namespace {

/// Bytes a client may send in one message: subscribe/unsubscribe requests are small.
constexpr size_t kMaxClientMessageBytes = 1u << 20;

std::string endpoint_text(const net::ip::tcp::socket& socket) {
    beast::error_code ec;
    const auto endpoint = socket.remote_endpoint(ec);
    if (ec) return "(unknown peer)";
    return endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
}

std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    const auto last = s.find_last_not_of(" \t");
    return s.substr(first, last - first + 1);
}

}  // namespace

bool offers_subprotocol(const std::string& header_value, const std::string& subprotocol) {
    size_t start = 0;
    while (start <= header_value.size()) {
        size_t comma = header_value.find(',', start);
        if (comma == std::string::npos) comma = header_value.size();
        if (trimmed(header_value.substr(start, comma - start)) == subprotocol) return true;
        start = comma + 1;
    }
    return false;
}

Session::Session(net::ip::tcp::socket socket, ServerState& state)
    : state_(state),
      peer_(endpoint_text(socket)),
      ws_(std::move(socket)),
      executor_(ws_.get_executor()) {}

void Session::run() {
    // Bounds the wait for the upgrade request; the WebSocket timeouts take over after it.
    beast::get_lowest_layer(ws_).expires_after(std::chrono::seconds(10));
    http::async_read(
        ws_.next_layer(), read_buffer_, request_,
        [self = shared_from_this()](beast::error_code ec, size_t) { self->on_request(ec); });
}

void Session::on_request(beast::error_code ec) {
    if (ec) {
        log::debug("foxglove ws: ", peer_, " sent no upgrade request: ", ec.message());
        return;
    }
    if (!websocket::is_upgrade(request_)) {
        refuse("expects a WebSocket upgrade request");
        return;
    }
    bool offered = false;
    for (const auto& field : request_) {
        if (field.name() == http::field::sec_websocket_protocol &&
            offers_subprotocol(std::string(field.value()), kSubprotocol)) {
            offered = true;
        }
    }
    if (!offered) {
        refuse(std::string("the client must offer WebSocket subprotocol ") + kSubprotocol);
        return;
    }
    beast::get_lowest_layer(ws_).expires_never();
    websocket::stream_base::timeout timeout;
    timeout.handshake_timeout = std::chrono::seconds(10);
    // Pings at half the idle time keep a quiet but live client (a browser answers them) and end a
    // client that stopped reading.
    timeout.idle_timeout = std::chrono::seconds(30);
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
        response.set(http::field::sec_websocket_protocol, kSubprotocol);
        response.set(http::field::server, "DetectFusion foxglove_ws");
    }));
    ws_.async_accept(request_,
                     [self = shared_from_this()](beast::error_code e) { self->on_accept(e); });
}

void Session::refuse(const std::string& why) {
    log::warn("foxglove ws: refused ", peer_, ": ", why);
    refusal_.version(request_.version());
    refusal_.result(http::status::bad_request);
    refusal_.set(http::field::content_type, "text/plain");
    refusal_.keep_alive(false);
    refusal_.body() = why + "\n";
    refusal_.prepare_payload();
    http::async_write(
        ws_.next_layer(), refusal_, [self = shared_from_this()](beast::error_code, size_t) {
            beast::error_code ignored;
            self->ws_.next_layer().socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
        });
}

void Session::on_accept(beast::error_code ec) {
    if (ec) {
        log::warn("foxglove ws: WebSocket handshake with ", peer_, " failed: ", ec.message());
        return;
    }
    ws_.read_message_max(kMaxClientMessageBytes);
    log::info("foxglove ws: client ", peer_, " connected");
    state_.open_session(shared_from_this());
    read_next();
}

void Session::read_next() {
    ws_.async_read(read_buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
        self->on_read(ec);
    });
}

void Session::on_read(beast::error_code ec) {
    if (ec) {
        end("read", ec);
        return;
    }
    if (ws_.got_text()) {
        handle_text(beast::buffers_to_string(read_buffer_.data()));
    } else {
        warn_client("binary client messages are not supported (no clientPublish capability)");
    }
    read_buffer_.consume(read_buffer_.size());
    read_next();
}

void Session::handle_text(const std::string& text) {
    const ClientRequest request = parse_client_request(text);
    switch (request.kind) {
        case ClientRequest::Kind::kSubscribe:
            subscribe(request);
            break;
        case ClientRequest::Kind::kUnsubscribe:
            unsubscribe(request);
            break;
        case ClientRequest::Kind::kUnsupported:
            warn_client("op \"" + request.op + "\" is not supported by this server; ignored");
            break;
        case ClientRequest::Kind::kInvalid:
            warn_client("ignored a message: " + request.error);
            break;
    }
}

void Session::subscribe(const ClientRequest& request) {
    for (const auto& [subscription_id, channel_id] : request.subscriptions) {
        if (!state_.has_channel(channel_id)) {
            warn_client("subscribe: there is no channel " + std::to_string(channel_id));
            continue;
        }
        std::string problem;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            bool channel_taken = false;
            for (const auto& entry : channel_of_subscription_) {
                channel_taken = channel_taken || entry.second == channel_id;
            }
            if (channel_of_subscription_.count(subscription_id) > 0) {
                problem = "subscription id " + std::to_string(subscription_id) + " is in use";
            } else if (channel_taken) {
                problem = "already subscribed to channel " + std::to_string(channel_id);
            } else {
                channel_of_subscription_.emplace(subscription_id, channel_id);
            }
        }
        if (!problem.empty()) {
            warn_client("subscribe: " + problem);
        } else {
            log::info("foxglove ws: ", peer_, " subscribed to channel ", channel_id);
        }
    }
}

void Session::unsubscribe(const ClientRequest& request) {
    for (uint32_t subscription_id : request.subscription_ids) {
        size_t erased = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            erased = channel_of_subscription_.erase(subscription_id);
        }
        if (erased == 0) {
            warn_client("unsubscribe: no subscription " + std::to_string(subscription_id));
        }
    }
}

void Session::warn_client(const std::string& message) {
    log::warn("foxglove ws: client ", peer_, ": ", message);
    queue_text(status_json(StatusLevel::kWarning, message));
}

Session::Queued Session::queue_message_data(
    uint32_t channel_id, uint64_t log_time_ns,
    const std::shared_ptr<const std::vector<uint8_t>>& payload, size_t max_queued_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return Queued::kNotSubscribed;
    const uint32_t* subscription_id = nullptr;
    for (const auto& entry : channel_of_subscription_) {
        if (entry.second == channel_id) subscription_id = &entry.first;
    }
    if (subscription_id == nullptr) return Queued::kNotSubscribed;
    const size_t bytes = kMessageDataHeaderSize + payload->size();
    if (queued_data_bytes_ > 0 && queued_data_bytes_ + bytes > max_queued_bytes) {
        if (!dropping_) {
            log::warn("foxglove ws: client ", peer_, " is slow: ", queued_data_bytes_,
                      " bytes queued, dropping its messages until the queue drains");
        }
        dropping_ = true;
        return Queued::kDropped;
    }
    if (dropping_) log::info("foxglove ws: client ", peer_, " takes messages again");
    dropping_ = false;
    Outgoing message;
    message.header = message_data_header(*subscription_id, log_time_ns);
    message.payload = payload;
    message.data_bytes = bytes;
    queued_data_bytes_ += bytes;
    push_locked(std::move(message));
    return Queued::kQueued;
}

void Session::queue_text(std::string json) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return;
    Outgoing message;
    message.is_text = true;
    message.text = std::move(json);
    push_locked(std::move(message));
}

bool Session::subscribes(uint32_t channel_id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return false;
    for (const auto& entry : channel_of_subscription_) {
        if (entry.second == channel_id) return true;
    }
    return false;
}

void Session::push_locked(Outgoing message) {
    queue_.push_back(std::move(message));
    if (!writing_) {
        writing_ = true;
        net::post(executor_, [self = shared_from_this()] { self->write_next(); });
    }
}

void Session::write_next() {
    const Outgoing* front = nullptr;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (queue_.empty() || closed_) {
            queue_.clear();
            queued_data_bytes_ = 0;
            writing_ = false;
            return;
        }
        // Stays valid while others push_back: a deque keeps its elements in place.
        front = &queue_.front();
    }
    auto on_done = [self = shared_from_this()](beast::error_code ec, size_t) {
        self->on_write(ec);
    };
    if (front->is_text) {
        ws_.text(true);
        ws_.async_write(net::buffer(front->text), std::move(on_done));
    } else {
        ws_.binary(true);
        const std::array<net::const_buffer, 2> buffers{net::buffer(front->header),
                                                       net::buffer(*front->payload)};
        ws_.async_write(buffers, std::move(on_done));
    }
}

void Session::on_write(beast::error_code ec) {
    bool was_data = false;
    bool more = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!ec) {
            was_data = !queue_.front().is_text;
            queued_data_bytes_ -= queue_.front().data_bytes;
            queue_.pop_front();
        }
        more = !ec && !closed_ && !queue_.empty();
        if (!more) {
            if (ec || closed_) {
                closed_ = true;
                queue_.clear();
                queued_data_bytes_ = 0;
            }
            writing_ = false;
        }
    }
    if (ec) {
        log::debug("foxglove ws: write to ", peer_, " failed: ", ec.message());
        close_now();  // ends the read loop too
        return;
    }
    if (was_data) state_.count_sent();
    if (more) write_next();
}

void Session::close() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;  // nothing new is queued or started
    }
    if (!ws_.is_open()) {  // still in the HTTP upgrade
        close_now();
        return;
    }
    // Beast sends the close frame after a write in flight; a write that never ends (a stalled
    // client) is ended by the server's close_now() after its grace period.
    ws_.async_close(websocket::close_code::going_away,
                    [self = shared_from_this()](beast::error_code) {});
}

void Session::close_now() {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
}

void Session::end(const char* what, beast::error_code ec) {
    if (ended_) return;
    ended_ = true;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
    }
    state_.close_session(this);
    if (ec == websocket::error::closed) {
        log::info("foxglove ws: client ", peer_, " disconnected");
    } else {
        log::info("foxglove ws: client ", peer_, " gone (", what, ": ", ec.message(), ")");
    }
    close_now();  // a write still in flight ends with it
}

}  // namespace df::foxglove
