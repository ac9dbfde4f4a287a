#pragma once
/// The one place that turns Cyclone DDS return codes into df::Status.
#include <dds/dds.h>

#include <string>

#include "core/status.hpp"

namespace df::dds {

/// ok for rc >= 0; otherwise a Status "<what>: <dds_strretcode(rc)>".
Status check(dds_return_t rc, const std::string& what);

}  // namespace df::dds
