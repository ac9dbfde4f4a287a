#include "slam_system/system_config.hpp"

namespace df::slam {

std::string validate(const SystemConfig& config) {
    // Each value against its range (slam.proto), section by section ...
    if (std::string e = validate(config.preprocess); !e.empty()) return "preprocess." + e;
    if (std::string e = validate(config.tracking); !e.empty()) return "tracking." + e;
    if (std::string e = params::check(config.map); !e.empty()) return "map." + e;
    const params::slam::Prediction& prediction = config.prediction;
    if (std::string e = params::check(prediction); !e.empty()) return "prediction." + e;
    if (std::string e = params::check(config.system); !e.empty()) return "system." + e;
    const DynamicsOptions& d = config.dynamics;
    const params::slam::Dynamics& dynamics = d;
    if (std::string e = params::check(dynamics); !e.empty()) return "dynamics." + e;
    if (std::string e = dynamics::validate(d.motion); !e.empty()) return "motion." + e;
    if (std::string e = dynamics::validate(d.invalid); !e.empty()) return "invalid." + e;
    if (std::string e = dynamics::validate(d.memory); !e.empty()) return "memory." + e;
    if (std::string e = dynamics::validate(d.propagation); !e.empty()) return "propagation." + e;
    if (std::string e = objects::validate(config.objects); !e.empty()) return "objects." + e;
    // ... then what one field's range cannot say.
    if (config.tracking.iterations.size() > static_cast<size_t>(config.preprocess.pyramid_levels)) {
        return "tracking.iterations has " + std::to_string(config.tracking.iterations.size()) +
               " levels but preprocess.pyramid_levels is " +
               std::to_string(config.preprocess.pyramid_levels);
    }
    if (d.refine_iterations.size() != config.tracking.iterations.size()) {
        return "dynamics.refine_iterations has " + std::to_string(d.refine_iterations.size()) +
               " levels, tracking.iterations " + std::to_string(config.tracking.iterations.size());
    }
    return "";
}

}  // namespace df::slam
