#pragma once
/// Internal to df_io_ply: the PLY header grammar and its scalar types.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::io::ply_detail {

enum class Scalar { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

/// Parses a PLY type name (char, uchar, ..., double, and int8 ... float64); false if unknown.
bool parse_scalar_type(const std::string& name, Scalar* type);

/// Bytes of one value of `type` in a binary file.
size_t scalar_size(Scalar type);

template <typename T>
double load(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
}

/// Reads a little-endian scalar (the hosts this builds on are little-endian).
inline double read_scalar(const char* p, Scalar type) {
    switch (type) {
        case Scalar::kInt8:
            return load<int8_t>(p);
        case Scalar::kUint8:
            return load<uint8_t>(p);
        case Scalar::kInt16:
            return load<int16_t>(p);
        case Scalar::kUint16:
            return load<uint16_t>(p);
        case Scalar::kInt32:
            return load<int32_t>(p);
        case Scalar::kUint32:
            return load<uint32_t>(p);
        case Scalar::kFloat32:
            return load<float>(p);
        case Scalar::kFloat64:
            return load<double>(p);
    }
    return 0;
}

struct Property {
    std::string name;
    Scalar type = Scalar::kFloat32;  ///< of the value, or of the items of a list
    bool is_list = false;
    Scalar count_type = Scalar::kUint8;
};

struct Element {
    std::string name;
    size_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    bool binary = false;
    std::vector<std::string> comments;
    std::vector<Element> elements;
    size_t data_offset = 0;  ///< bytes from the start of the file
    int data_line = 0;       ///< line number of the first data line (ASCII)
};

/// Parses the header at the start of `bytes` (the whole file). Errors are "file:line: what".
Result<Header> parse_header(const std::string& file, const std::string& bytes);

/// `line` without a trailing '\r' (files written on Windows).
std::string strip_cr(std::string line);

}  // namespace df::io::ply_detail
