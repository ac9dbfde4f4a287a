#pragma once
/// A WebSocket client for the tests, written with Beast: connects to 127.0.0.1:port offering a
/// subprotocol, reads JSON and binary Message Data, sends text. Every operation gives up after a
/// timeout (so a broken server fails a test instead of hanging it).
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace df::foxglove::test {

namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;

/// One Message Data frame, decoded.
struct DataMessage {
    uint8_t opcode = 0;
    uint32_t subscription_id = 0;
    uint64_t log_time_ns = 0;
    std::vector<uint8_t> payload;
};

class TestClient {
  public:
    /// Connects and does the WebSocket handshake offering `subprotocols` (a Sec-WebSocket-Protocol
    /// value; empty = no header). error() tells why when it failed.
    TestClient(uint16_t port, const std::string& subprotocols) : ws_(io_) {
        ws_.read_message_max(64u << 20);
        auto ec = run([&](auto done) {
            ws_.next_layer().async_connect({boost::asio::ip::make_address("127.0.0.1"), port},
                                           done);
        });
        if (ec) {
            error_ = "connect: " + ec.message();
            return;
        }
        ws_.set_option(websocket::stream_base::decorator([subprotocols](auto& request) {
            if (!subprotocols.empty()) {
                request.set(beast::http::field::sec_websocket_protocol, subprotocols);
            }
        }));
        ec = run([&](auto done) { ws_.async_handshake(response_, "127.0.0.1", "/", done); });
        if (ec) error_ = "handshake: " + ec.message();
    }

    bool connected() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    /// The HTTP response to the upgrade request (status, selected subprotocol).
    const websocket::response_type& response() const { return response_; }

    /// The next message, which must be text holding JSON; nullopt on timeout, error or binary.
    std::optional<nlohmann::json> read_json(std::chrono::seconds timeout = kTimeout) {
        if (!read(timeout) || !ws_.got_text()) return std::nullopt;
        auto j = nlohmann::json::parse(beast::buffers_to_string(buffer_.data()), nullptr, false);
        if (j.is_discarded()) return std::nullopt;
        return j;
    }

    /// The next message, which must be binary with at least the 13-byte header.
    std::optional<DataMessage> read_data(std::chrono::seconds timeout = kTimeout) {
        if (!read(timeout) || ws_.got_text()) return std::nullopt;
        const std::string bytes = beast::buffers_to_string(buffer_.data());
        if (bytes.size() < 13) return std::nullopt;
        DataMessage m;
        m.opcode = static_cast<uint8_t>(bytes[0]);
        for (int i = 0; i < 4; ++i) {
            m.subscription_id |= uint32_t{static_cast<uint8_t>(bytes[1 + i])} << (8 * i);
        }
        for (int i = 0; i < 8; ++i) {
            m.log_time_ns |= uint64_t{static_cast<uint8_t>(bytes[5 + i])} << (8 * i);
        }
        m.payload.assign(bytes.begin() + 13, bytes.end());
        return m;
    }

    /// Reads one message and returns the error (e.g. websocket::error::closed once closed).
    beast::error_code read_error(std::chrono::seconds timeout = kTimeout) {
        buffer_.consume(buffer_.size());
        last_read_error_ = run([&](auto done) { ws_.async_read(buffer_, done); }, timeout);
        return last_read_error_;
    }
    /// The result of the last read (e.g. why read_data() gave nullopt).
    beast::error_code last_read_error() const { return last_read_error_; }
    websocket::close_reason close_reason() const { return ws_.reason(); }

    bool send_text(const std::string& text) {
        ws_.text(true);
        return !run([&](auto done) { ws_.async_write(boost::asio::buffer(text), done); });
    }
    bool send_binary(const std::vector<uint8_t>& bytes) {
        ws_.binary(true);
        return !run([&](auto done) { ws_.async_write(boost::asio::buffer(bytes), done); });
    }

  private:
    static constexpr std::chrono::seconds kTimeout{10};

    bool read(std::chrono::seconds timeout) { return !read_error(timeout); }

    /// Starts an async operation with a completion handler and runs the io_context until it
    /// completes or `timeout` passes (then the socket is closed and a timeout error returned).
    template <typename Start>
    beast::error_code run(Start start, std::chrono::seconds timeout = kTimeout) {
        std::optional<beast::error_code> result;
        start([&result](beast::error_code ec, auto&&...) { result = ec; });
        io_.restart();
        io_.run_for(timeout);
        if (result) return *result;
        beast::error_code ignored;
        ws_.next_layer().close(ignored);
        io_.restart();
        io_.run();
        return beast::error::timeout;
    }

    boost::asio::io_context io_;
    websocket::stream<boost::asio::ip::tcp::socket> ws_;
    websocket::response_type response_;
    beast::flat_buffer buffer_;
    std::string error_;
    beast::error_code last_read_error_;
};

}  // namespace df::foxglove::test
