#pragma once
/// SlamParams (protobuf, common/config/slam.proto) onto df::slam::SystemConfig: each field set in
/// the message replaces the parameter of the same dotted name (parameters.hpp); unset fields keep
/// the library's defaults.
#include <string>
#include <vector>

#include "core/status.hpp"
#include "slam.pb.h"
#include "slam_system/system_config.hpp"

namespace df::slam {

/// Applies every field set in `params` to `config` (config::apply_params per section).
/// kInvalidArgument naming the section when the proto and the generated structs disagree.
Status apply(const config::SlamParams& params, SystemConfig* config);

/// The values of `config` as a SlamParams with every field set (for checking the library's
/// defaults against the ranges slam.proto declares).
config::SlamParams to_params(const SystemConfig& config);

/// `df_slam params`: every parameter with its library default, allowed range and unit (both from
/// slam.proto, declared once there) and meaning (the parameter table), one per line.
std::string params_table(const SystemConfig& config);

/// Names present in one of the proto and the parameter table but not in the other ("proto
/// only: x" / "table only: y"); empty when they agree (a unit test keeps it so).
std::vector<std::string> mismatches();

}  // namespace df::slam
