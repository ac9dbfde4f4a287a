// An independent reader opens what our writer wrote: tests/js/mcap_dump.mjs reads the file with
// @mcap/core (Foxglove's TypeScript library: indexed and streaming readers, CRCs checked) and
// prints JSON, which must match what was written. Fails (never skips) when node or
// tests/js/node_modules is missing: run deploy/setup.sh.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "mcap/mcap_writer.hpp"
#include "mcap_test_util.hpp"
#include "sha256.hpp"

#ifndef DF_JS_TESTS_DIR
#error "DF_JS_TESTS_DIR (the tests/js folder) must be defined by CMake"
#endif
#ifndef DF_NODE_EXECUTABLE
#define DF_NODE_EXECUTABLE "node"
#endif

namespace df::mcap {
namespace {

using test::WrittenMessage;

const std::string kFrameIdl =
    "module df { module msg {\n"
    "  @final struct RgbdFrame { uint64 stamp_ns; uint32 seq; sequence<uint8> rgb; };\n"
    "}; };\n";
const std::string kPoseIdl =
    "module df { module msg {\n  struct Pose { uint64 stamp_ns; double t[3]; double q[4]; };\n}; "
    "};\n";

std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

/// Runs `command`, returns its stdout and sets `exit_code`.
std::string run(const std::string& command, int& exit_code) {
    std::string out;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) {
        exit_code = -1;
        return out;
    }
    char buffer[65536];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) out.append(buffer, n);
    const int status = ::pclose(pipe);
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

TEST(Sha256, KnownDigests) {
    EXPECT_EQ(test::sha256_hex(reinterpret_cast<const uint8_t*>("abc"), 3),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(test::sha256_hex(nullptr, 0),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    EXPECT_EQ(
        test::sha256_hex(reinterpret_cast<const uint8_t*>(two_blocks.data()), two_blocks.size()),
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(McapJsReader, FoxgloveMcapCoreReadsWhatWeWrote) {
    const std::string node = DF_NODE_EXECUTABLE;
    const std::string js_dir = DF_JS_TESTS_DIR;
    int code = 0;
    run(shell_quote(node) + " --version", code);
    ASSERT_EQ(code, 0) << "Node.js ('" << node << "') cannot be run. This test needs node and the "
                       << "npm packages in " << js_dir << ": run deploy/setup.sh";
    ASSERT_TRUE(std::filesystem::exists(js_dir + "/node_modules/@mcap/core/package.json"))
        << "@mcap/core is not installed in " << js_dir << "/node_modules: run deploy/setup.sh "
        << "(or `npm install` in " << js_dir << ")";

    // Two channels, 20 messages (one a 1.5 MB frame), interleaved and slightly out of order.
    const std::string path = test::temp_path("js_reader.mcap");
    std::vector<WrittenMessage> written;
    {
        auto writer = Writer::open(path);
        ASSERT_TRUE(writer.is_ok()) << writer.status().to_string();
        Writer& w = **writer;
        const uint16_t frame = w.add_schema("df::msg::RgbdFrame", "omgidl", kFrameIdl).value();
        const uint16_t pose = w.add_schema("df::msg::Pose", "omgidl", kPoseIdl).value();
        const uint16_t rgbd =
            w.add_channel(frame, "/camera/rgbd", "cdr", {{"source", "tum"}}).value();
        const uint16_t poses = w.add_channel(pose, "/slam/pose", "cdr").value();
        const uint64_t t0 = 1'700'000'000'123'456'789ull;  // beyond 2^53: must survive as text
        for (uint32_t i = 0; i < 10; ++i) {
            const size_t frame_size = i == 4 ? 1'500'000 : 2'000 + 13 * i;
            written.push_back({rgbd, 100 + i, t0 + i * 33'333'333ull,
                               t0 + i * 33'333'333ull - 2'000, test::cdr_payload(frame_size, i)});
            written.push_back({poses, i, t0 + i * 33'333'333ull + (i % 3 == 0 ? 1 : 40'000'000),
                               t0 + i * 33'333'333ull, test::cdr_payload(64, 1000 + i)});
        }
        for (const WrittenMessage& m : written) {
            ASSERT_TRUE(w.write(m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns,
                                m.data.data(), m.data.size())
                            .is_ok());
        }
        ASSERT_TRUE(w.close().is_ok());
    }

    const std::string output = run(
        shell_quote(node) + " " + shell_quote(js_dir + "/mcap_dump.mjs") + " " + shell_quote(path),
        code);
    ASSERT_EQ(code, 0) << "mcap_dump.mjs failed (its reason is above); stdout:\n" << output;
    const nlohmann::json dump = nlohmann::json::parse(output, nullptr, false);
    ASSERT_FALSE(dump.is_discarded()) << "mcap_dump.mjs printed no JSON:\n" << output;

    EXPECT_EQ(dump["profile"], "");
    EXPECT_EQ(dump["library"], "detectfusion");
    ASSERT_EQ(dump["schemas"].size(), 2u);
    EXPECT_EQ(dump["schemas"][0]["name"], "df::msg::RgbdFrame");
    EXPECT_EQ(dump["schemas"][0]["encoding"], "omgidl");
    EXPECT_EQ(dump["schemas"][0]["dataLength"], kFrameIdl.size());
    EXPECT_EQ(
        dump["schemas"][0]["dataSha256"],
        test::sha256_hex(reinterpret_cast<const uint8_t*>(kFrameIdl.data()), kFrameIdl.size()));
    EXPECT_EQ(dump["schemas"][1]["name"], "df::msg::Pose");
    ASSERT_EQ(dump["channels"].size(), 2u);
    EXPECT_EQ(dump["channels"][0]["topic"], "/camera/rgbd");
    EXPECT_EQ(dump["channels"][0]["messageEncoding"], "cdr");
    EXPECT_EQ(dump["channels"][0]["schemaId"], 1);
    EXPECT_EQ(dump["channels"][0]["metadata"]["source"], "tum");
    EXPECT_EQ(dump["channels"][1]["topic"], "/slam/pose");
    EXPECT_EQ(dump["channels"][1]["schemaId"], 2);
    EXPECT_EQ(dump["statistics"]["messageCount"], "20");
    EXPECT_EQ(dump["statistics"]["channelMessageCounts"]["1"], "10");
    EXPECT_EQ(dump["statistics"]["channelMessageCounts"]["2"], "10");

    std::vector<WrittenMessage> expected = written;
    std::stable_sort(expected.begin(), expected.end(),
                     [](const auto& a, const auto& b) { return a.log_time_ns < b.log_time_ns; });
    const nlohmann::json& messages = dump["messages"];
    ASSERT_EQ(messages.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        SCOPED_TRACE("message " + std::to_string(i));
        const WrittenMessage& m = expected[i];
        EXPECT_EQ(messages[i]["channelId"], m.channel_id);
        EXPECT_EQ(messages[i]["sequence"], m.sequence);
        EXPECT_EQ(messages[i]["logTime"], std::to_string(m.log_time_ns));
        EXPECT_EQ(messages[i]["publishTime"], std::to_string(m.publish_time_ns));
        EXPECT_EQ(messages[i]["dataLength"], m.data.size());
        EXPECT_EQ(messages[i]["sha256"], test::sha256_hex(m.data.data(), m.data.size()));
    }
    std::remove(path.c_str());
}

}  // namespace
}  // namespace df::mcap
