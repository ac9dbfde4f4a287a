#pragma once
/// Checking a loaded configuration against what its .proto declares (options.proto: range,
/// non_empty, choices; every float finite), plus the cross-field rules of each service config
/// that a per-field declaration cannot say. Called once at start (service::load_config).
#include <google/protobuf/message.h>

#include <string>

#include "core/status.hpp"

namespace df::config {

/// Every field set in `message` (nested messages and repeated fields included) against its
/// declared rules, then the cross-field rules of the message's type (validate_rules.cpp).
/// kInvalidArgument naming the field path ("slam.map.confidence_sigma"), the value found and
/// what is allowed, e.g. "slam.map.confidence_sigma is 0, allowed: > 0 and <= 100".
Status check(const google::protobuf::Message& message);

/// Only the declared per-field rules (no cross-field rules); `prefix` starts the field paths.
Status check_fields(const google::protobuf::Message& message, const std::string& prefix = "");

/// What a field allows, as text: "> 0 and <= 1000 [x]", "one of auto|shm|udp", "not empty",
/// "finite"; "" when there is no rule (booleans, enums, unconstrained integers and strings).
std::string allowed_text(const google::protobuf::FieldDescriptor* field);

/// What one value of the field allows (allowed_text without "each" for repeated fields).
std::string rule_text(const google::protobuf::FieldDescriptor* field);

/// The declared unit of a field ("" when none).
std::string unit_of(const google::protobuf::FieldDescriptor* field);

/// Every field of the message type (nested types walked), one line each:
/// "  dds.ns  default \"df\"  not empty", for a service's --help.
std::string options_help(const google::protobuf::Descriptor* type);

/// The cross-field rules of the service configs (validate_rules.cpp), by message type; ok for a
/// type with none.
Status check_rules(const google::protobuf::Message& message);

}  // namespace df::config
