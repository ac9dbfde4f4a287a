#include "core/status.hpp"

namespace df {

const char* to_string(StatusCode code) {
    switch (code) {
        case StatusCode::kOk:
            return "ok";
        case StatusCode::kInvalidArgument:
            return "invalid argument";
        case StatusCode::kNotFound:
            return "not found";
        case StatusCode::kIoError:
            return "I/O error";
        case StatusCode::kUnavailable:
            return "unavailable";
        case StatusCode::kTimeout:
            return "timeout";
        case StatusCode::kResourceExhausted:
            return "resource exhausted";
        case StatusCode::kEndOfStream:
            return "end of stream";
        case StatusCode::kInternal:
            return "internal error";
    }
    return "unknown";
}

std::string Status::to_string() const {
    if (is_ok()) return "ok";
    return std::string(df::to_string(code_)) + ": " + message_;
}

Status Status::with_context(const std::string& context) const {
    if (is_ok()) return *this;
    return Status(code_, context + ": " + message_);
}

}  // namespace df
