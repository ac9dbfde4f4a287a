#include "foxglove_ws/websocket_server.hpp"

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <thread>
#include <utility>

#include "core/log.hpp"
#include "foxglove_ws/server_state.hpp"
#include "foxglove_ws/session.hpp"

namespace df::foxglove {
namespace net = boost::asio;
using net::ip::tcp;

namespace {

/// How long the destructor lets clients take their close frame before their sockets are closed.
constexpr auto kCloseGrace = std::chrono::seconds(1);

std::string host_port(const std::string& address, uint16_t port) {
    const bool ipv6 = address.find(':') != std::string::npos;
    return (ipv6 ? "[" + address + "]" : address) + ":" + std::to_string(port);
}

std::string new_session_id() {
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    return std::to_string(std::chrono::duration_cast<std::chrono::nanoseconds>(now).count());
}

}  // namespace

struct WebSocketServer::Impl {
    explicit Impl(const ServerOptions& options) : state(options, new_session_id()) {}

    void accept_next();
    void stop();
    void wait_for_sessions(std::chrono::steady_clock::time_point deadline);

    ServerState state;
    net::io_context io{1};
    tcp::acceptor acceptor{io};
    net::steady_timer retry_timer{io};     // after a failed accept (e.g. out of descriptors)
    net::steady_timer shutdown_timer{io};  // polls for sessions still closing in stop()
    std::vector<std::weak_ptr<Session>> sessions;  // every connection, I/O thread only
    uint16_t port = 0;
    std::thread thread;
};

void WebSocketServer::Impl::accept_next() {
    acceptor.async_accept(io, [this](boost::system::error_code ec, tcp::socket socket) {
        if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
        if (ec) {
            log::warn("foxglove ws: accept failed on port ", port, ": ", ec.message(),
                      "; retrying in 100 ms");
            retry_timer.expires_after(std::chrono::milliseconds(100));
            retry_timer.async_wait([this](boost::system::error_code e) {
                if (!e) accept_next();
            });
            return;
        }
        auto session = std::make_shared<Session>(std::move(socket), state);
        sessions.erase(std::remove_if(sessions.begin(), sessions.end(),
                                      [](const auto& s) { return s.expired(); }),
                       sessions.end());
        sessions.push_back(session);
        session->run();
        accept_next();
    });
}

void WebSocketServer::Impl::stop() {
    net::post(io, [this] {
        boost::system::error_code ignored;
        acceptor.close(ignored);
        retry_timer.cancel();
        for (const auto& weak : sessions) {
            if (auto session = weak.lock()) session->close();
        }
        wait_for_sessions(std::chrono::steady_clock::now() + kCloseGrace);
    });
    if (thread.joinable()) thread.join();
}

void WebSocketServer::Impl::wait_for_sessions(std::chrono::steady_clock::time_point deadline) {
    sessions.erase(
        std::remove_if(sessions.begin(), sessions.end(), [](const auto& s) { return s.expired(); }),
        sessions.end());
    if (sessions.empty()) return;  // nothing left to run: io.run() returns
    if (std::chrono::steady_clock::now() >= deadline) {
        for (const auto& weak : sessions) {
            if (auto session = weak.lock()) session->close_now();
        }
        return;
    }
    shutdown_timer.expires_after(std::chrono::milliseconds(10));
    shutdown_timer.async_wait(
        [this, deadline](boost::system::error_code) { wait_for_sessions(deadline); });
}

Result<std::unique_ptr<WebSocketServer>> WebSocketServer::start(const ServerOptions& options) {
    const std::string where = host_port(options.address, options.port);
    boost::system::error_code ec;
    const net::ip::address address = net::ip::make_address(options.address, ec);
    if (ec) {
        return error(StatusCode::kInvalidArgument,
                     "foxglove websocket server: address '" + options.address +
                         "' is not an IPv4 or IPv6 address (" + ec.message() + ")");
    }
    auto impl = std::make_unique<Impl>(options);
    const tcp::endpoint endpoint(address, options.port);
    impl->acceptor.open(endpoint.protocol(), ec);
    if (!ec) impl->acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) impl->acceptor.bind(endpoint, ec);
    if (!ec) impl->acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec) {
        return error(StatusCode::kUnavailable,
                     "foxglove websocket server: cannot listen on " + where + ": " + ec.message());
    }
    impl->port = impl->acceptor.local_endpoint().port();
    impl->accept_next();
    Impl* raw = impl.get();
    impl->thread = std::thread([raw] { raw->io.run(); });
    log::info("foxglove websocket server '", options.name, "' listening on ws://",
              host_port(options.address, impl->port));
    return std::unique_ptr<WebSocketServer>(new WebSocketServer(std::move(impl)));
}

WebSocketServer::WebSocketServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

WebSocketServer::~WebSocketServer() { impl_->stop(); }

uint32_t WebSocketServer::add_channel(const ChannelInfo& channel) {
    return impl_->state.add_channel(channel);
}

void WebSocketServer::publish(uint32_t channel_id, uint64_t log_time_ns,
                              std::shared_ptr<const std::vector<uint8_t>> payload) {
    impl_->state.publish(channel_id, log_time_ns, payload);
}

bool WebSocketServer::has_subscribers(uint32_t channel_id) const {
    return impl_->state.subscriber_count(channel_id) > 0;
}

size_t WebSocketServer::subscriber_count(uint32_t channel_id) const {
    return impl_->state.subscriber_count(channel_id);
}

uint16_t WebSocketServer::port() const { return impl_->port; }
size_t WebSocketServer::client_count() const { return impl_->state.client_count(); }
uint64_t WebSocketServer::dropped_messages() const { return impl_->state.dropped_messages(); }
uint64_t WebSocketServer::sent_messages() const { return impl_->state.sent_messages(); }

}  // namespace df::foxglove
