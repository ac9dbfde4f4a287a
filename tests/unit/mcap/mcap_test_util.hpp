#pragma once
// Helpers shared by the df_mcap tests: temp paths, synthetic CDR payloads, whole-file I/O.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace df::mcap::test {

/// A path in the test temp dir, unique to this process and `name`.
inline std::string temp_path(const std::string& name) {
    return ::testing::TempDir() + "df_mcap_" + std::to_string(::getpid()) + "_" + name;
}

/// `size` bytes that look like a CDR sample: the 4-byte little-endian encapsulation header
/// (0x00 0x01 0x00 0x00), then bytes from a seeded generator.
inline std::vector<uint8_t> cdr_payload(size_t size, uint32_t seed) {
    std::vector<uint8_t> out(size);
    const uint8_t header[4] = {0x00, 0x01, 0x00, 0x00};
    uint32_t state = seed * 2654435761u + 1u;
    for (size_t i = 0; i < size; ++i) {
        state = state * 1664525u + 1013904223u;
        out[i] = i < 4 ? header[i] : uint8_t(state >> 24);
    }
    return out;
}

inline std::vector<uint8_t> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_file(const std::string& path, const uint8_t* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// One message as given to Writer::write, to compare with what a reader returns.
struct WrittenMessage {
    uint16_t channel_id = 0;
    uint32_t sequence = 0;
    uint64_t log_time_ns = 0;
    uint64_t publish_time_ns = 0;
    std::vector<uint8_t> data;
};

}  // namespace df::mcap::test
