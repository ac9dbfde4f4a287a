#pragma once
#include "temp_folder.hpp"
/// Helpers for the df_io_ply tests: a temporary folder, writing and reading raw bytes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace df::io::test {

using df::test::TempFolder;  // tests/support/temp_folder.hpp

inline void write_file(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
    ASSERT_TRUE(out.good()) << "cannot write " << path;
}

inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Appends the bytes of `value` (little-endian host) to `data`.
template <typename T>
void put(std::string* data, T value) {
    data->append(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace df::io::test
