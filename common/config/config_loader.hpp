#pragma once
/// Service configuration: a protobuf message read from a text-format file, then overridden by
/// "--set 'field: value'" flags (any field, text format), and logged in full at start.
#include <google/protobuf/message.h>

#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::config {

/// Merges the text-format file (if path is not empty) and then each override into message.
/// Errors name the file (with line and column) or the override that failed to parse.
Status load(const std::string& path, const std::vector<std::string>& overrides,
            google::protobuf::Message* message);

/// Every field with its effective value (defaults included), one "name: value" per line.
std::string describe(const google::protobuf::Message& message);

}  // namespace df::config
