#pragma once
// SHA-256 (FIPS 180-4), only for comparing message bytes with what node's crypto reports.
#include <cstddef>
#include <cstdint>
#include <string>

namespace df::mcap::test {

/// Lower-case hex digest of `size` bytes at `data`.
std::string sha256_hex(const uint8_t* data, size_t size);

}  // namespace df::mcap::test
