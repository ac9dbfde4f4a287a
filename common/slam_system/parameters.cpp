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
    DynamicsOptions& d = c->dynamics;
    dynamics::MotionSegmentationConfig& ms = d.motion;
    dynamics::InvalidMaskConfig& iv = d.invalid;
    objects::ObjectMapsConfig& o = c->objects;
    return {
        {"preprocess.min_depth_m", "depth below this is invalid", &p.min_depth_m},
        {"preprocess.max_depth_m", "depth at or beyond this is invalid", &p.max_depth_m},
        {"preprocess.bilateral_sigma_space_px", "bilateral filter spatial sigma (normals)",
         &p.bilateral_sigma_space_px},
        {"preprocess.bilateral_sigma_depth_m", "bilateral filter range sigma",
         &p.bilateral_sigma_depth_m},
        {"preprocess.bilateral_radius_px", "bilateral filter half window", &p.bilateral_radius_px},
        {"preprocess.normal_baseline_px", "normals from central differences this many pixels apart",
         &p.normal_baseline_px},
        {"preprocess.pyramid_levels", "pyramid levels (level 0 = full resolution)",
         &p.pyramid_levels},
        {"preprocess.pyramid_max_depth_diff_m",
         "depth left out of a 2x2 average when this far from the block's reference",
         &p.pyramid_max_depth_diff_m},

        {"tracking.iterations", "Gauss-Newton iterations per level, finest first", &t.iterations},
        {"tracking.pixel_step", "pixel step per level, finest first", &t.pixel_step},
        {"tracking.icp_max_distance_m", "ICP association distance gate", &t.icp_max_distance_m},
        {"tracking.icp_max_normal_sin", "ICP association gate on the sine of normal angle",
         &t.icp_max_normal_sin},
        {"tracking.use_rgb", "use the photometric term", &t.use_rgb},
        {"tracking.icp_weight", "weight w of ICP in A_rgb + w^2 A_icp at the finest level",
         &t.icp_weight},
        {"tracking.icp_weight_coarse", "w at the coarser levels (ICP's wide basin first)",
         &t.icp_weight_coarse},
        {"tracking.adaptive_weights", "each term scaled by its own residual spread",
         &t.adaptive_weights},
        {"tracking.rgb_min_gradient",
         "minimum gradient of photometric pixels per level, finest first", &t.rgb_min_gradient},
        {"tracking.rgb_max_depth_difference_m",
         "photometric pixels need frame and model depth this close", &t.rgb_max_depth_difference_m},
        {"tracking.max_depth_m",
         "points farther along z are left out of tracking (0: preprocessing's cut only)",
         &t.max_depth_m},
        {"tracking.icp_huber_m", "Huber threshold of ICP residuals", &t.icp_huber_m},
        {"tracking.rgb_huber", "Huber threshold of photometric residuals", &t.rgb_huber},
        {"tracking.min_update_translation_m", "a level ends below this update",
         &t.min_update_translation_m},
        {"tracking.min_update_rotation_rad", "a level ends below this update",
         &t.min_update_rotation_rad},
        {"tracking.min_inlier_ratio", "lost below this ICP inlier fraction", &t.min_inlier_ratio},
        {"tracking.min_frame_inlier_ratio",
         "lost below this fraction of valid frame pixels being inliers", &t.min_frame_inlier_ratio},
        {"tracking.min_inliers", "lost below this many ICP inliers", &t.min_inliers},
        {"tracking.max_icp_rmse_m", "lost above this inlier RMS residual", &t.max_icp_rmse_m},
        {"tracking.min_condition", "lost below this eigenvalue ratio of the 6x6 system",
         &t.min_condition},
        {"tracking.max_translation_m", "lost when moved further from the initial guess",
         &t.max_translation_m},
        {"tracking.max_rotation_rad", "lost when turned further from the initial guess",
         &t.max_rotation_rad},

        {"map.stable_confidence", "a surfel is stable from this confidence", &m.stable_confidence},
        {"map.confidence_sigma", "observation weight exp(-r^2 / 2 sigma^2), r radial",
         &m.confidence_sigma},
        {"map.max_depth_difference_m", "association gate along z", &m.max_depth_difference_m},
        {"map.max_normal_angle_rad", "association gate on the normal angle",
         &m.max_normal_angle_rad},
        {"map.merge_radius_factor", "geometry merges when new radius < this x old",
         &m.merge_radius_factor},
        {"map.min_abs_normal_z", "floor of |n_z| in the radius of grazing observations",
         &m.min_abs_normal_z},
        {"map.unstable_max_unseen_frames",
         "unstable surfels not fused for longer than this are removed",
         &m.unstable_max_unseen_frames},
        {"map.association_window_px",
         "half window of the index image searched for a surfel to fuse into",
         &m.association_window_px},
        {"map.active_time_window_frames", "surfels unseen this long become inactive",
         &m.active_time_window_frames},
        {"map.max_surfels", "capacity; new observations dropped when full", &m.max_surfels},
        {"map.remove_free_space", "remove or weaken surfels the frame sees through",
         &m.remove_free_space},
        {"map.free_space_margin_m", "seen-through margin (plus the z^2 term)",
         &m.free_space_margin_m},
        {"map.free_space_margin_per_m2", "seen-through margin growing with z^2",
         &m.free_space_margin_per_m2},
        {"map.free_space_window_px", "half window that must all be seen through",
         &m.free_space_window_px},
        {"map.free_space_penalty", "confidence lost per unit weight by a stable surfel",
         &m.free_space_penalty},

        {"prediction.max_depth_m", "surfels farther along z are not rendered (0: no limit)",
         &r.max_depth_m},
        {"prediction.splat", "render discs (true) or one pixel per surfel", &r.splat},
        {"prediction.max_splat_radius_px", "bound of a surfel's footprint", &r.max_splat_radius_px},
        {"prediction.min_cos_incidence", "grazing pixels below this cosine not covered",
         &r.min_cos_incidence},
        {"prediction.layer_tolerance_m",
         "discs this close in depth are one layer (pixel takes the nearest centre)",
         &r.layer_tolerance_m},
        {"prediction.layer_tolerance_per_m2", "layer tolerance growing with z^2",
         &r.layer_tolerance_per_m2},
        {"prediction.threads", "render threads (0 = all)", &r.threads},

        {"system.processing_downscale", "1 = full resolution, 2 = half", &s.processing_downscale},
        {"system.predict_min_confidence", "confidence of surfels rendered for tracking",
         &s.predict_min_confidence},
        {"system.bootstrap_frames", "frames rendering every surfel for tracking",
         &s.bootstrap_frames},
        {"system.constant_velocity", "initial guess moved on by the last motion",
         &s.constant_velocity},
        {"system.fuse_when_lost", "fuse frames whose tracking is lost", &s.fuse_when_lost},
        {"system.associate_by_prediction", "fusion associates through the predicted index image",
         &s.associate_by_prediction},
        {"dynamics.use_segments", "leave the frame's object instances out of the static map",
         &d.use_segments},
        {"dynamics.motion_segmentation", "find unknown movers in stage 1's residuals",
         &d.motion_segmentation},
        {"dynamics.carry_forward", "last frame's motion segments lower the evidence needed",
         &d.carry_forward},
        {"dynamics.refine_iterations", "stage 2 iterations per level, finest first",
         &d.refine_iterations},
        {"dynamics.max_rescue_fraction",
         "stage 2 rescues a rejected stage 1 only below this fraction left out as moving",
         &d.max_rescue_fraction},

        {"motion.max_residual_m", "residuals clipped to this before 2-means", &ms.max_residual_m},
        {"motion.min_residual_m", "a dynamic pixel's residual exceeds this (plus the z^2 term)",
         &ms.min_residual_m},
        {"motion.min_residual_per_m2", "noise floor growing with z^2", &ms.min_residual_per_m2},
        {"motion.min_centroid_gap_m", "no motion when the 2-means centroids are closer",
         &ms.min_centroid_gap_m},
        {"motion.min_dynamic_fraction", "no motion below this fraction of dynamic pixels",
         &ms.min_dynamic_fraction},
        {"motion.min_segment_fraction", "a segment is dynamic from this fraction of its pixels",
         &ms.min_segment_fraction},
        {"motion.carried_segment_fraction", "the same for a segment dynamic last frame",
         &ms.carried_segment_fraction},
        {"motion.carry_min_overlap", "a segment was dynamic when the carried mask covers this",
         &ms.carry_min_overlap},
        {"motion.min_segment_pixels", "a dynamic segment has at least this many dynamic pixels",
         &ms.min_segment_pixels},
        {"motion.min_region_pixels", "without segments, dynamic regions at least this large",
         &ms.min_region_pixels},
        {"motion.dilate_px", "the motion mask grows by this", &ms.dilate_px},
        {"motion.min_photometric",
         "intensity change that counts as a segment's motion evidence (0 off)",
         &ms.min_photometric},

        {"invalid.non_rigid", "leave non-rigid instances (persons) out", &iv.non_rigid},
        {"invalid.rigid", "leave rigid instances out (until object maps)", &iv.rigid},
        {"invalid.unknown", "leave instances of unknown kind out (ground-truth masks)",
         &iv.unknown},
        {"invalid.instance_dilate_px", "instance masks grow by this", &iv.instance_dilate_px},
        {"invalid.non_rigid_box_depth_m",
         "a person also claims its box's pixels within its depth range widened by this (0 off)",
         &iv.non_rigid_box_depth_m},
        {"invalid.fuse_behind_model_m",
         "invalid pixels this far behind the model are fused (clears ghosts; 0 never)",
         &iv.fuse_behind_model_m},

        {"memory.frames",
         "a rigid instance pixel stays left out this many frames after its last detection (0 off)",
         &d.memory.frames},
        {"memory.max_depth_difference_m", "... while the frame's depth there stays this close",
         &d.memory.max_depth_difference_m},
        {"memory.max_depth_difference_per_m2", "... plus this times depth^2",
         &d.memory.max_depth_difference_per_m2},

        {"objects.enabled", "rigid objects get maps of their own (false: invalid.rigid decides)",
         &o.enabled},
        {"objects.match_min_overlap",
         "an instance matches a map whose rendering covers this fraction of its pixels",
         &o.association.min_overlap},
        {"objects.class_must_agree", "... and only a map of its class", &o.association.class_must_agree},
        {"objects.any_class_overlap", "... or any class when this much of it is covered",
         &o.association.any_class_overlap},
        {"objects.depth_tolerance_m",
         "a map claims its rendered pixels where the frame's depth agrees within this",
         &o.association.depth_tolerance_m},
        {"objects.depth_tolerance_per_m2", "... plus this times depth^2",
         &o.association.depth_tolerance_per_m2},
        {"objects.min_silhouette_fraction",
         "a map the detector missed is seen when the frame agrees with this much of it",
         &o.association.min_silhouette_fraction},
        {"objects.background_tolerance_m",
         "a pixel the static map explains within this is the background's, not an object's",
         &o.association.background_tolerance_m},
        {"objects.background_tolerance_per_m2", "... plus this times depth^2",
         &o.association.background_tolerance_per_m2},
        {"objects.min_create_pixels",
         "an unmatched rigid instance this big (processing resolution) may create a map",
         &o.min_create_pixels},
        {"objects.create_after_frames", "... once seen on this many consecutive frames",
         &o.create_after_frames},
        {"objects.candidate_min_iou", "... each sighting's box overlapping the last this much (IoU)",
         &o.candidate_min_iou},
        {"objects.retire_after_frames", "a map that claims no pixel this long is retired",
         &o.retire_after_frames},
        {"objects.revive_max_distance_m",
         "a new sighting this close to a retired map of its class revives it", &o.revive_max_distance_m},
        {"objects.max_objects", "live object maps at most (creations past it are counted)",
         &o.max_objects},
        {"objects.min_inliers", "ICP inliers an object's tracking needs", &o.min_inliers},
        {"objects.min_track_pixels", "an object is tracked only with this many pixels",
         &o.min_track_pixels},
        {"objects.max_surfels", "surfels per object map at most", &o.max_surfels},
        {"objects.static_explained_fraction",
         "a rigid instance the static map explains this much of stays in it (1 never)",
         &o.static_explained_fraction},
        {"objects.fuse_erode_px", "an instance's mask shrinks this much before it is fused",
         &o.fuse_erode_px},
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
        text += p.name + " = " + value_text(p) + "\n";
    }
    return text;
}

}  // namespace df::slam
