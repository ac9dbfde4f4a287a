#include "slam_system/system_config.hpp"

namespace df::slam {

std::string validate(const SystemConfig& config) {
    if (std::string e = validate(config.preprocess); !e.empty()) return e;
    if (std::string e = validate(config.tracking); !e.empty()) return e;
    const SystemOptions& s = config.system;
    if (s.processing_downscale != 1 && s.processing_downscale != 2) {
        return "system.processing_downscale must be 1 or 2, got " +
               std::to_string(s.processing_downscale);
    }
    if (s.bootstrap_frames < 0) {
        return "system.bootstrap_frames must be >= 0, got " + std::to_string(s.bootstrap_frames);
    }
    if (!(s.predict_min_confidence >= 0.f)) {
        return "system.predict_min_confidence must be >= 0, got " +
               std::to_string(s.predict_min_confidence);
    }
    if (config.tracking.iterations.size() > static_cast<size_t>(config.preprocess.pyramid_levels)) {
        return "tracking.iterations has " + std::to_string(config.tracking.iterations.size()) +
               " levels but preprocess.pyramid_levels is " +
               std::to_string(config.preprocess.pyramid_levels);
    }
    if (config.map.max_surfels == 0) return "map.max_surfels must be > 0";
    const DynamicsOptions& d = config.dynamics;
    if (d.refine_iterations.size() != config.tracking.iterations.size()) {
        return "dynamics.refine_iterations has " + std::to_string(d.refine_iterations.size()) +
               " levels, tracking.iterations " + std::to_string(config.tracking.iterations.size());
    }
    for (int i : d.refine_iterations)
        if (i < 0) return "dynamics.refine_iterations must be >= 0, got " + std::to_string(i);
    if (!(d.max_rescue_fraction >= 0.f && d.max_rescue_fraction <= 1.f))
        return "dynamics.max_rescue_fraction must be in [0, 1], got " +
               std::to_string(d.max_rescue_fraction);
    if (std::string e = dynamics::validate(d.motion); !e.empty()) return "motion." + e;
    if (std::string e = dynamics::validate(d.invalid); !e.empty()) return "invalid." + e;
    if (std::string e = dynamics::validate(d.memory); !e.empty()) return "memory." + e;
    if (std::string e = objects::validate(config.objects); !e.empty()) return e;
    if (config.map.association_window_px < 0 || config.map.association_window_px > 4) {
        return "map.association_window_px must be 0..4, got " +
               std::to_string(config.map.association_window_px);
    }
    return "";
}

}  // namespace df::slam
