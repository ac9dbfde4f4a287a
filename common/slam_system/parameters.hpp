#pragma once
/// The parameters of SystemConfig by dotted name ("tracking.icp_max_distance_m") with a one-line
/// meaning, for configuration files, command-line overrides, logs and docs. Derived from the
/// structs generated from common/config/slam.proto, where each parameter (default, range, unit,
/// meaning) is declared once (`df_slam params` prints them all).
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "core/status.hpp"
#include "slam_system/system_config.hpp"

namespace df::slam {

struct Parameter {
    std::string name;  ///< "<section>.<field>", sections: preprocess tracking map prediction system
    std::string meaning;
    std::variant<float*, double*, int*, bool*, size_t*, std::vector<int>*, std::vector<float>*>
        value;  ///< points into the SystemConfig the table was made for
};

/// Calls f(name, section) for each section of slam.proto's SlamParams ("preprocess", ...) with
/// the generated struct SystemConfig holds it as: where each section lives is said here only.
template <class F>
void for_each_section(SystemConfig* c, F&& f) {
    f("preprocess", c->preprocess);
    f("tracking", c->tracking);
    f("map", c->map);
    f("prediction", static_cast<params::slam::Prediction&>(c->prediction));
    f("system", c->system);
    f("dynamics", static_cast<params::slam::Dynamics&>(c->dynamics));
    f("motion", c->dynamics.motion);
    f("invalid", c->dynamics.invalid);
    f("memory", c->dynamics.memory);
    f("propagation", c->dynamics.propagation);
    f("objects", c->objects);
}

/// Every parameter of `config` (pointers into it; the table is valid while config is).
std::vector<Parameter> parameters(SystemConfig* config);

/// The value as text: "0.1", "true", "10,5,4".
std::string value_text(const Parameter& parameter);

/// Sets the value from text (the format value_text writes). kInvalidArgument naming the
/// parameter and the text when it does not parse.
Status set_value(const Parameter& parameter, const std::string& text);

/// "name = value" per line, every parameter, in table order.
std::string describe(const SystemConfig& config);

}  // namespace df::slam
