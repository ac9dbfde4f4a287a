#pragma once
/// A CDR writer for Foxglove's "cdr" message encoding: the 4-byte encapsulation header of plain
/// little-endian CDR (XCDR1, 0x00 0x01 0x00 0x00), then each value aligned to its own size (8 for
/// doubles) counted from after the header, strings as a uint32 length with the terminating NUL
/// included, sequences as a uint32 count then the elements. What Foxglove's omgidl reader
/// (@foxglove/omgidl-serialization) decodes for final structs.
#include <cstdint>
#include <string>
#include <vector>

namespace df::foxglove {

class CdrWriter {
  public:
    CdrWriter();
    void u8(uint8_t v);
    void boolean(bool v) { u8(v ? 1 : 0); }
    void u32(uint32_t v);
    void i32(int32_t v);
    void f64(double v);
    void string(const std::string& v);
    /// A sequence<uint8>: count, then the bytes.
    void bytes(const uint8_t* data, size_t size);
    /// Appends bytes as they are (the elements of a sequence<uint8> whose count was written).
    void append(const uint8_t* data, size_t size) { raw(data, size); }
    /// Reserves room for `size` more bytes (large images).
    void reserve(size_t size) { buf_.reserve(buf_.size() + size); }
    /// The message; the writer is empty afterwards.
    std::vector<uint8_t> take() { return std::move(buf_); }

  private:
    void align(size_t n);
    void raw(const void* data, size_t size);
    std::vector<uint8_t> buf_;
};

}  // namespace df::foxglove
