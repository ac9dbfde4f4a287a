#include "recorded_sample.hpp"

#include "dds/cdr.hpp"
#include "dds/sample_check.hpp"

namespace df::tap {

Status decode_recorded(const dds::TypeInfo& type, const mcap::Message& message,
                       const RecordRef& where, void* sample) {
    Status s = dds::from_cdr(type.descriptor, message.data, message.size, sample);
    if (s) s = dds::check_sample(type, sample);
    if (s) return s;
    return s.with_context(where.file + ": message " + std::to_string(where.index) + " (topic '" +
                          where.topic + "', sequence " + std::to_string(message.sequence) +
                          ", log time " + std::to_string(message.log_time_ns) + " ns)");
}

}  // namespace df::tap
