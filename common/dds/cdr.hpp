#pragma once
/// CDR (de)serialization of any topic type, as recorded in MCAP files: the 4-byte
/// encapsulation header {0x00, 0x01, 0, 0} (CDR, little endian, XCDR1) followed by the data.
#include <dds/dds.h>

#include <cstdint>
#include <vector>

#include "core/status.hpp"

namespace df::dds {

/// Serializes a sample of the descriptor's type.
/// Empty when the sample holds a value its type does not allow (an enum out of range).
std::vector<uint8_t> to_cdr(const dds_topic_descriptor_t* desc, const void* sample);

/// Validates and deserializes CDR bytes into sample (desc->m_size bytes, zeroed by the caller).
/// Free sequences afterwards with dds_sample_free(sample, desc, DDS_FREE_CONTENTS).
Status from_cdr(const dds_topic_descriptor_t* desc, const uint8_t* data, size_t size, void* sample);

}  // namespace df::dds
