#pragma once
/// Human-readable text of one sample (tap echo): headers and small fields in full, image arrays
/// summarised and truncated, like `ros2 topic echo`.
#include <string>

#include "dds/msg_types.hpp"

namespace df::tap {

/// YAML-like text of a sample of the given type; max_items limits listed array elements.
std::string print_sample(const dds::TypeInfo& type, const void* sample, int max_items = 8);

}  // namespace df::tap
