#pragma once
/// tap play's boundary: a sample read from a recording is as untrusted as one from the network
/// (a recording can be corrupt, truncated by hand or written by another tool), so it is decoded
/// and checked with check_sample() before it is published.
#include <cstdint>
#include <string>

#include "core/status.hpp"
#include "dds/msg_types.hpp"
#include "mcap/mcap_types.hpp"

namespace df::tap {

/// Which record of which file a message is, for errors a user can find it by.
struct RecordRef {
    std::string file;    ///< the MCAP file
    uint64_t index = 0;  ///< the message's place among the file's messages, from 0, log-time order
    std::string topic;   ///< the channel's topic in the file
};

/// Deserializes the CDR bytes of `message` into `sample` (type.descriptor->m_size bytes, zeroed
/// by the caller) and checks the sample with check_sample(). Error (the sample must then not be
/// published): "<file>: message <index> (topic '<topic>', sequence <s>, log time <t> ns): <why>",
/// where <why> names the field, its value and the allowed range, e.g.
/// "RgbdFrame.width 1000 > MAX_WIDTH 640". Either way, the caller frees the sample's sequences
/// with dds_sample_free(sample, desc, DDS_FREE_CONTENTS).
Status decode_recorded(const dds::TypeInfo& type, const mcap::Message& message,
                       const RecordRef& where, void* sample);

}  // namespace df::tap
