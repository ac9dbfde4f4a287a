#include "dds/dds_error.hpp"

namespace df::dds {

Status check(dds_return_t rc, const std::string& what) {
    if (rc >= 0) return Status::ok();
    StatusCode code = StatusCode::kInternal;
    switch (rc) {
        case DDS_RETCODE_BAD_PARAMETER:
            code = StatusCode::kInvalidArgument;
            break;
        case DDS_RETCODE_TIMEOUT:
            code = StatusCode::kTimeout;
            break;
        case DDS_RETCODE_OUT_OF_RESOURCES:
            code = StatusCode::kResourceExhausted;
            break;
        case DDS_RETCODE_PRECONDITION_NOT_MET:
        case DDS_RETCODE_NOT_ENABLED:
        case DDS_RETCODE_ALREADY_DELETED:
            code = StatusCode::kUnavailable;
            break;
        default:
            break;
    }
    return Status(code, what + ": " + dds_strretcode(rc));
}

}  // namespace df::dds
