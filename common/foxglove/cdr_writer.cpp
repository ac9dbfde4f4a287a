#include "foxglove/cdr_writer.hpp"

#include <cstring>

namespace df::foxglove {
namespace {
constexpr size_t kHeader = 4;
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "CDR_LE is written in host order");
}  // namespace

CdrWriter::CdrWriter() : buf_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::align(size_t n) {
    const size_t offset = buf_.size() - kHeader;
    buf_.resize(buf_.size() + (n - offset % n) % n, 0);
}

void CdrWriter::raw(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    buf_.insert(buf_.end(), p, p + size);
}

void CdrWriter::u8(uint8_t v) { buf_.push_back(v); }

void CdrWriter::u32(uint32_t v) {
    align(4);
    raw(&v, 4);
}

void CdrWriter::i32(int32_t v) {
    align(4);
    raw(&v, 4);
}

void CdrWriter::f64(double v) {
    align(8);
    raw(&v, 8);
}

void CdrWriter::string(const std::string& v) {
    u32(static_cast<uint32_t>(v.size() + 1));
    raw(v.data(), v.size());
    buf_.push_back(0);
}

void CdrWriter::bytes(const uint8_t* data, size_t size) {
    u32(static_cast<uint32_t>(size));
    if (size > 0) raw(data, size);
}

}  // namespace df::foxglove
