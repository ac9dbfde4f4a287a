// A server for tests/js/ws_client_check.mjs (the real @foxglove/ws-protocol client), run by
// tests/integration/foxglove_ws_js_test.sh. Listens on a free port of 127.0.0.1 and prints
// "port N"; advertises /df/test/blob (cdr, omgidl schema df::test::Blob) and /df/test/other;
// once /df/test/blob has a subscriber, publishes one message on /df/test/other and kMessages on
// /df/test/blob. Exits 0 when all of those were written to the client and the client has closed,
// 1 (reason on stderr) when that does not happen within --timeout-s seconds (default 30).
//
// The contract with ws_client_check.mjs (which computes the same values itself):
//   message k (k = 0..3): CDR little endian of df::test::Blob{seq = k, data = n_k bytes},
//   n_k = {1, 1000, 65539, 1000000}, data[i] = (k * 37 + i * 11) & 0xff,
//   log time = 1700000000000000000 + k * 1000000007 ns.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/log.hpp"
#include "foxglove_ws/websocket_server.hpp"

namespace {

constexpr uint32_t kMessages = 4;
constexpr size_t kSizes[kMessages] = {1, 1000, 65539, 1000000};
constexpr uint64_t kFirstLogTimeNs = 1700000000000000000ull;
constexpr uint64_t kLogTimeStepNs = 1000000007ull;

void put_u32_le(std::vector<uint8_t>& out, size_t at, uint32_t v) {
    for (size_t i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));
}

/// df::test::Blob { uint32 seq; sequence<uint8> data; } as CDR (XCDR1) little endian.
std::shared_ptr<const std::vector<uint8_t>> blob(uint32_t seq) {
    const size_t n = kSizes[seq];
    auto out = std::make_shared<std::vector<uint8_t>>(12 + n);
    (*out)[1] = 0x01;  // encapsulation CDR_LE {0, 1}, options {0, 0}
    put_u32_le(*out, 4, seq);
    put_u32_le(*out, 8, static_cast<uint32_t>(n));
    for (size_t i = 0; i < n; ++i) (*out)[12 + i] = static_cast<uint8_t>(seq * 37 + i * 11);
    return out;
}

template <typename Pred>
bool wait_until(Pred done, std::chrono::steady_clock::time_point deadline) {
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

int fail(const std::string& why) {
    std::fprintf(stderr, "ws_js_test_server: %s\n", why.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    int timeout_s = 30;
    if (argc == 3 && std::strcmp(argv[1], "--timeout-s") == 0) timeout_s = std::atoi(argv[2]);
    df::log::set_component("ws_js_test_server");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);

    df::foxglove::ServerOptions options;
    options.port = 0;
    options.name = "DetectFusion ws test";
    auto started = df::foxglove::WebSocketServer::start(options);
    if (!started.is_ok()) return fail(started.status().to_string());
    auto& server = *started.value();
    const uint32_t blob_channel =
        server.add_channel({"/df/test/blob", "cdr", "df::test::Blob", "omgidl",
                            "module df { module test {\n"
                            "  struct Blob { uint32 seq; sequence<uint8> data; };\n"
                            "}; };\n"});
    const uint32_t other_channel = server.add_channel(
        {"/df/test/other", "json", "Other", "jsonschema", R"({"type":"object"})"});
    std::printf("port %u\n", static_cast<unsigned>(server.port()));
    std::fflush(stdout);

    if (!wait_until([&] { return server.has_subscribers(blob_channel); }, deadline)) {
        return fail("no client subscribed to /df/test/blob");
    }
    server.publish(other_channel, 1, std::make_shared<std::vector<uint8_t>>(3, uint8_t{'x'}));
    for (uint32_t k = 0; k < kMessages; ++k) {
        server.publish(blob_channel, kFirstLogTimeNs + k * kLogTimeStepNs, blob(k));
    }
    if (!wait_until([&] { return server.sent_messages() == kMessages; }, deadline)) {
        return fail("sent " + std::to_string(server.sent_messages()) + " of " +
                    std::to_string(kMessages) + " messages");
    }
    if (!wait_until([&] { return server.client_count() == 0; }, deadline)) {
        return fail("the client did not close");
    }
    if (server.dropped_messages() != 0) return fail("messages were dropped");
    return 0;
}
