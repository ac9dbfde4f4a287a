#include "slam_system/parameters.hpp"

#include <charconv>
#include <cstdlib>
#include <sstream>

namespace df::slam {
namespace {

template <typename T>
bool parse_number(const std::string& text, T* out) {
    if (text.empty()) return false;
    char* end = nullptr;
    if constexpr (std::is_same_v<T, float>) {
        *out = std::strtof(text.c_str(), &end);
    } else if constexpr (std::is_same_v<T, double>) {
        *out = std::strtod(text.c_str(), &end);
    } else if constexpr (std::is_same_v<T, int>) {
        const long v = std::strtol(text.c_str(), &end, 10);
        if (v < -2147483647L || v > 2147483647L) return false;
        *out = static_cast<int>(v);
    } else {
        if (text[0] == '-') return false;
        *out = static_cast<T>(std::strtoull(text.c_str(), &end, 10));
    }
    return end != nullptr && *end == '\0';
}

template <typename T>
bool parse_list(const std::string& text, std::vector<T>* out) {
    std::vector<T> values;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        T v{};
        if (!parse_number(item, &v)) return false;
        values.push_back(v);
    }
    if (values.empty()) return false;
    *out = std::move(values);
    return true;
}

template <typename T>
std::string number_text(T v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

std::vector<Parameter> parameters(SystemConfig* c) {
    PreprocessConfig& p = c->preprocess;
    TrackingConfig& t = c->tracking;
    map::SurfelMapConfig& m = c->map;
    map::PredictionConfig& r = c->prediction;
    SystemOptions& s = c->system;
    return {
        {"preprocess.min_depth_m", "m", "depth below this is invalid", &p.min_depth_m},
        {"preprocess.max_depth_m", "m", "depth at or beyond this is invalid", &p.max_depth_m},
        {"preprocess.bilateral_sigma_space_px", "px", "bilateral filter spatial sigma (normals)",
         &p.bilateral_sigma_space_px},
        {"preprocess.bilateral_sigma_depth_m", "m", "bilateral filter range sigma",
         &p.bilateral_sigma_depth_m},
        {"preprocess.bilateral_radius_px", "px", "bilateral filter half window",
         &p.bilateral_radius_px},
        {"preprocess.normal_baseline_px", "px",
         "normals from central differences this many pixels apart", &p.normal_baseline_px},
        {"preprocess.pyramid_levels", "", "pyramid levels (level 0 = full resolution)",
         &p.pyramid_levels},
        {"preprocess.pyramid_max_depth_diff_m", "m",
         "depth left out of a 2x2 average when this far from the block's reference",
         &p.pyramid_max_depth_diff_m},

        {"tracking.iterations", "", "Gauss-Newton iterations per level, finest first",
         &t.iterations},
        {"tracking.pixel_step", "px", "pixel step per level, finest first", &t.pixel_step},
        {"tracking.icp_max_distance_m", "m", "ICP association distance gate",
         &t.icp_max_distance_m},
        {"tracking.icp_max_normal_sin", "", "ICP association gate on the sine of normal angle",
         &t.icp_max_normal_sin},
        {"tracking.use_rgb", "", "use the photometric term", &t.use_rgb},
        {"tracking.icp_weight", "", "weight w of ICP in A_rgb + w^2 A_icp", &t.icp_weight},
        {"tracking.rgb_min_gradient", "intensity/px",
         "minimum gradient of photometric pixels per level, finest first", &t.rgb_min_gradient},
        {"tracking.rgb_max_depth_difference_m", "m",
         "photometric pixels need frame and model depth this close", &t.rgb_max_depth_difference_m},
        {"tracking.max_depth_m", "m",
         "points farther along z are left out of tracking (0: preprocessing's cut only)",
         &t.max_depth_m},
        {"tracking.icp_huber_m", "m", "Huber threshold of ICP residuals", &t.icp_huber_m},
        {"tracking.rgb_huber", "intensity", "Huber threshold of photometric residuals",
         &t.rgb_huber},
        {"tracking.min_update_translation_m", "m", "a level ends below this update",
         &t.min_update_translation_m},
        {"tracking.min_update_rotation_rad", "rad", "a level ends below this update",
         &t.min_update_rotation_rad},
        {"tracking.min_inlier_ratio", "", "lost below this ICP inlier fraction",
         &t.min_inlier_ratio},
        {"tracking.min_frame_inlier_ratio", "",
         "lost below this fraction of valid frame pixels being inliers",
         &t.min_frame_inlier_ratio},
        {"tracking.min_inliers", "", "lost below this many ICP inliers", &t.min_inliers},
        {"tracking.max_icp_rmse_m", "m", "lost above this inlier RMS residual", &t.max_icp_rmse_m},
        {"tracking.min_condition", "", "lost below this eigenvalue ratio of the 6x6 system",
         &t.min_condition},
        {"tracking.max_translation_m", "m", "lost when moved further from the initial guess",
         &t.max_translation_m},
        {"tracking.max_rotation_rad", "rad", "lost when turned further from the initial guess",
         &t.max_rotation_rad},

        {"map.stable_confidence", "", "a surfel is stable from this confidence",
         &m.stable_confidence},
        {"map.confidence_sigma", "", "observation weight exp(-r^2 / 2 sigma^2), r radial",
         &m.confidence_sigma},
        {"map.max_depth_difference_m", "m", "association gate along z",
         &m.max_depth_difference_m},
        {"map.max_normal_angle_rad", "rad", "association gate on the normal angle",
         &m.max_normal_angle_rad},
        {"map.merge_radius_factor", "", "geometry merges when new radius < this x old",
         &m.merge_radius_factor},
        {"map.min_abs_normal_z", "", "floor of |n_z| in the radius of grazing observations",
         &m.min_abs_normal_z},
        {"map.unstable_max_unseen_frames", "frames",
         "unstable surfels not fused for longer than this are removed",
         &m.unstable_max_unseen_frames},
        {"map.association_window_px", "px",
         "half window of the index image searched for a surfel to fuse into",
         &m.association_window_px},
        {"map.active_time_window_frames", "frames", "surfels unseen this long become inactive",
         &m.active_time_window_frames},
        {"map.max_surfels", "surfels", "capacity; new observations dropped when full",
         &m.max_surfels},
        {"map.remove_free_space", "", "remove or weaken surfels the frame sees through",
         &m.remove_free_space},
        {"map.free_space_margin_m", "m", "seen-through margin (plus the z^2 term)",
         &m.free_space_margin_m},
        {"map.free_space_margin_per_m2", "1/m", "seen-through margin growing with z^2",
         &m.free_space_margin_per_m2},
        {"map.free_space_window_px", "px", "half window that must all be seen through",
         &m.free_space_window_px},
        {"map.free_space_penalty", "", "confidence lost per unit weight by a stable surfel",
         &m.free_space_penalty},

        {"prediction.max_depth_m", "m", "surfels farther along z are not rendered (0: no limit)",
         &r.max_depth_m},
        {"prediction.splat", "", "render discs (true) or one pixel per surfel", &r.splat},
        {"prediction.max_splat_radius_px", "px", "bound of a surfel's footprint",
         &r.max_splat_radius_px},
        {"prediction.min_cos_incidence", "", "grazing pixels below this cosine not covered",
         &r.min_cos_incidence},
        {"prediction.layer_tolerance_m", "m",
         "discs this close in depth are one layer (pixel takes the nearest centre)",
         &r.layer_tolerance_m},
        {"prediction.layer_tolerance_per_m2", "1/m", "layer tolerance growing with z^2",
         &r.layer_tolerance_per_m2},
        {"prediction.threads", "", "render threads (0 = all)", &r.threads},

        {"system.processing_downscale", "", "1 = full resolution, 2 = half",
         &s.processing_downscale},
        {"system.predict_min_confidence", "", "confidence of surfels rendered for tracking",
         &s.predict_min_confidence},
        {"system.bootstrap_frames", "frames", "frames rendering every surfel for tracking",
         &s.bootstrap_frames},
        {"system.constant_velocity", "", "initial guess moved on by the last motion",
         &s.constant_velocity},
        {"system.fuse_when_lost", "", "fuse frames whose tracking is lost", &s.fuse_when_lost},
        {"system.associate_by_prediction", "",
         "fusion associates through the predicted index image", &s.associate_by_prediction},
    };
}

std::string value_text(const Parameter& parameter) {
    return std::visit(
        [](auto* v) -> std::string {
            using T = std::remove_pointer_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                return *v ? "true" : "false";
            } else if constexpr (std::is_same_v<T, std::vector<int>> ||
                                 std::is_same_v<T, std::vector<float>>) {
                std::string text;
                for (size_t i = 0; i < v->size(); ++i)
                    text += (i ? "," : "") + number_text((*v)[i]);
                return text;
            } else {
                return number_text(*v);
            }
        },
        parameter.value);
}

Status set_value(const Parameter& parameter, const std::string& text) {
    const bool ok = std::visit(
        [&](auto* v) -> bool {
            using T = std::remove_pointer_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                if (text == "true" || text == "1") return *v = true, true;
                if (text == "false" || text == "0") return *v = false, true;
                return false;
            } else if constexpr (std::is_same_v<T, std::vector<int>> ||
                                 std::is_same_v<T, std::vector<float>>) {
                return parse_list(text, v);
            } else {
                T parsed{};
                if (!parse_number(text, &parsed)) return false;
                *v = parsed;
                return true;
            }
        },
        parameter.value);
    if (ok) return Status::ok();
    return error(StatusCode::kInvalidArgument,
                 "parameter " + parameter.name + ": cannot read '" + text + "' as its value");
}

std::string describe(const SystemConfig& config) {
    SystemConfig copy = config;
    std::string text;
    for (const Parameter& p : parameters(&copy)) {
        text += p.name + " = " + value_text(p);
        if (!p.unit.empty()) text += "  [" + p.unit + "]";
        text += "\n";
    }
    return text;
}

}  // namespace df::slam
