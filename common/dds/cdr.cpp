#include "dds/cdr.hpp"

#include <dds/ddsi/ddsi_cdrstream.h>

#include <cstring>
#include <string>

namespace df::dds {
namespace {
constexpr uint32_t kXcdr1 = 1;
constexpr uint8_t kCdrLe = 0x01;  // encapsulation id 0x0001: CDR little endian
}  // namespace

std::vector<uint8_t> to_cdr(const dds_topic_descriptor_t* desc, const void* sample) {
    dds_ostreamLE_t os;
    dds_ostreamLE_init(&os, desc->m_size + 64, kXcdr1);
    if (dds_stream_writeLE(&os, static_cast<const char*>(sample), desc->m_ops) == nullptr) {
        // A value the type does not allow (an enum out of range): nothing is half-written.
        dds_ostreamLE_fini(&os);
        return {};
    }
    std::vector<uint8_t> out(4 + os.x.m_index);
    out[0] = 0x00;
    out[1] = kCdrLe;
    out[2] = out[3] = 0;
    std::memcpy(out.data() + 4, os.x.m_buffer, os.x.m_index);
    dds_ostreamLE_fini(&os);
    return out;
}

Status from_cdr(const dds_topic_descriptor_t* desc, const uint8_t* data, size_t size,
                void* sample) {
    if (size < 4) {
        return Status(StatusCode::kInvalidArgument, "CDR sample of " + std::to_string(size) +
                                                        " bytes is shorter than its 4-byte header");
    }
    if (data[0] != 0x00 || data[1] != kCdrLe) {
        return Status(StatusCode::kInvalidArgument,
                      "unsupported CDR encapsulation " + std::to_string(data[0]) + "," +
                          std::to_string(data[1]) + " (expected 0,1: CDR little endian)");
    }
    if (size == 4) {
        return Status(StatusCode::kInvalidArgument,
                      std::string("CDR sample has no data after its header (a ") +
                          desc->m_typename + " has at least its Header)");
    }
    // Validate first (normalize checks bounds and sequence lengths); it works in place.
    std::vector<char> body(reinterpret_cast<const char*>(data) + 4,
                           reinterpret_cast<const char*>(data) + size);
    uint32_t off = 0;
    if (dds_stream_normalize_data(body.data(), &off, static_cast<uint32_t>(body.size()), false,
                                  kXcdr1, desc->m_ops) == nullptr) {
        return Status(StatusCode::kInvalidArgument,
                      std::string("CDR data is not a valid ") + desc->m_typename);
    }
    dds_istream_t is;
    dds_istream_init(&is, static_cast<uint32_t>(body.size()), body.data(), kXcdr1);
    dds_stream_read(&is, static_cast<char*>(sample), desc->m_ops);
    dds_istream_fini(&is);
    return Status::ok();
}

}  // namespace df::dds
