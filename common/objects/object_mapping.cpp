// Step 3 of object_maps.hpp: fusion of the tracked maps (at the sensor's resolution or the
// processing resolution), free-space carving, creation and retirement.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "objects/object_maps.hpp"
#include "objects/object_maps_detail.hpp"
#include "slam/pose.hpp"

namespace df::objects {

cv::Mat ObjectMaps::fusable(const dynamics::LabelImage& instances, uint16_t id,
                            const cv::Mat& depth_m, const cv::Mat& background_depth_m) const {
    cv::Mat mask = instances.labels == id;
    if (config_.fuse_erode_px > 0) {
        const int k = 2 * config_.fuse_erode_px + 1;
        cv::erode(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    }
    if (background_depth_m.empty() || background_depth_m.size() != depth_m.size()) return mask;
    for (int v = 0; v < mask.rows; ++v) {
        uint8_t* m = mask.ptr<uint8_t>(v);
        const float* d = depth_m.ptr<float>(v);
        const float* b = background_depth_m.ptr<float>(v);
        for (int u = 0; u < mask.cols; ++u)
            if (m[u] && agrees_with_background(d[u], b[u], config_.association)) m[u] = 0;
    }
    return mask;
}

Result<map::FusionStats> ObjectMaps::fuse_pixels(
    ObjectMap& o, const slam::Frame& frame, const cv::Mat& rgb, const io::RgbdImage& full_image,
    const cv::Mat& keep, const cv::Rect& roi, const Eigen::Isometry3d& object_T_camera,
    int map_time, const cv::Mat& background_depth_m, bool create_surfels) {
    const cv::Size size = frame.levels[0].depth_m.size();
    const int f = size.width > 0 ? full_image.depth.cols / size.width : 0;
    // Confirming a silhouette stays at the processing resolution: its pixels are the map's
    // rendering where the depth agrees, and at the sensor's resolution their fringe pulled
    // the default data's car 1.4 to 1.9 cm off its track (docs/objects.md).
    // An object that fills much of the view is fused at the processing resolution: the cost per
    // frame stays bounded whatever its size in the image (full_resolution_max_pixels).
    const bool small = config_.full_resolution_max_pixels == 0 ||
                       cv::countNonZero(keep(roi & cv::Rect(cv::Point(0, 0), size))) <=
                           config_.full_resolution_max_pixels;
    const bool full = config_.fuse_full_resolution && small && create_surfels && f > 1 &&
                      full_image.depth.cols == f * size.width &&
                      full_image.depth.rows == f * size.height &&
                      full_image.rgb.size() == full_image.depth.size();
    if (!full) {
        cv::Rect used;
        const slam::Frame part = slam::crop(frame, roi, &used);
        if (used.empty()) return map::FusionStats{};
        return o.map.fuse(part, rgb(used), keep(used) == 0, object_T_camera, map_time, false,
                          prediction_, create_surfels);
    }
    const cv::Rect in_roi = roi & cv::Rect(cv::Point(0, 0), size);
    if (in_roi.empty()) return map::FusionStats{};
    const cv::Rect box = cv::boundingRect(keep(in_roi)) + in_roi.tl();
    if (box.empty()) return map::FusionStats{};
    // The part of the sensor image under the pixels to fuse, with room for the filters that
    // make its normals (they need neighbours).
    slam::PreprocessConfig pre = preprocess_;
    pre.pyramid_levels = 1;
    pre.bilateral_sigma_space_px *= static_cast<float>(f);
    pre.bilateral_radius_px = std::min(16, pre.bilateral_radius_px * f);
    pre.normal_baseline_px = std::min(8, pre.normal_baseline_px * f);
    const int margin = pre.bilateral_radius_px + pre.normal_baseline_px;
    const cv::Rect part_box = cv::Rect(box.x * f - margin, box.y * f - margin,
                                       box.width * f + 2 * margin, box.height * f + 2 * margin) &
                              cv::Rect(cv::Point(0, 0), full_image.depth.size());
    if (part_box.width < 8 || part_box.height < 8) return map::FusionStats{};
    io::RgbdImage part = full_image;
    part.rgb = full_image.rgb(part_box);
    part.depth = full_image.depth(part_box);
    part.intrinsics.cx -= part_box.x;
    part.intrinsics.cy -= part_box.y;
    Result<slam::Frame> fine = slam::preprocess(part, pre);
    if (!fine) return fine.status();
    fine->sensor_size = full_image.depth.size();
    // A sensor pixel is fused when the processing-resolution pixel of its block is, with its
    // depth within full_resolution_max_step_m of that pixel's (not the far side of an edge the
    // block straddles) and not explained by the background.
    const cv::Mat& depth = fine->levels[0].depth_m;
    const cv::Mat& coarse = frame.levels[0].depth_m;
    const bool background = !background_depth_m.empty() && background_depth_m.size() == size;
    cv::Mat left_out(part_box.size(), CV_8UC1, cv::Scalar(255));
    for (int y = 0; y < part_box.height; ++y) {
        const int v = (part_box.y + y) / f;
        const uint8_t* k = keep.ptr<uint8_t>(v);
        const float* c = coarse.ptr<float>(v);
        const float* b = background ? background_depth_m.ptr<float>(v) : nullptr;
        const float* d = depth.ptr<float>(y);
        uint8_t* out = left_out.ptr<uint8_t>(y);
        for (int x = 0; x < part_box.width; ++x) {
            const int u = (part_box.x + x) / f;
            if (k[u] == 0 || !(d[x] > 0.f) ||
                !depth_agrees(d[x], c[u], config_.full_resolution_max_step_m, 0.f)) {
                continue;
            }
            if (b != nullptr && agrees_with_background(d[x], b[u], config_.association)) continue;
            out[x] = 0;
        }
    }
    return o.map.fuse(*fine, part.rgb, left_out, object_T_camera, map_time, false, prediction_,
                      create_surfels);
}

Status ObjectMaps::map(const slam::Frame& frame, const cv::Mat& rgb,
                       const io::RgbdImage& full_image, const dynamics::LabelImage& instances,
                       const Eigen::Isometry3d& world_T_camera, int map_time, uint64_t frame_number,
                       const cv::Mat& background_depth_m, ObjectFrame* of) {
    for (size_t k = 0; k < of->live.size(); ++k) {
        ObjectMap& o = objects_[of->live[k]];
        ObjectReport& r = of->reports[k];
        const Eigen::Isometry3d object_T_camera = o.map.world_T_map().inverse() * world_T_camera;
        if (r.pixels > 0) o.last_seen_frame = frame_number;
        const uint64_t before = o.map.map().total_rejected_by_capacity();
        cv::Rect used;
        const slam::Frame part = slam::crop(frame, of->rois[k], &used);
        if (r.tracked && r.instance != 0 && !used.empty()) {
            // Only what the detector's instance shows is fused: a silhouette's depth-agreeing
            // pixels would let the map grow into the floor it stands on.
            cv::Mat keep =
                fusable(instances, r.instance, frame.levels[0].depth_m, background_depth_m);
            if (!of->grown.empty()) keep |= of->grown;
            keep &= of->object_ids == static_cast<uint16_t>(o.id);
            auto fused = fuse_pixels(o, frame, rgb, full_image, keep, used, object_T_camera,
                                     map_time, background_depth_m, true);
            if (!fused) return fused.status();
        } else if (config_.fuse_silhouette && r.tracked && r.instance == 0 && r.pixels > 0 &&
                   !used.empty()) {
            // Missed by the detector, tracked on its silhouette: those pixels confirm the
            // surfels they agree with; nothing new is made.
            const cv::Mat keep = of->object_ids == static_cast<uint16_t>(o.id);
            auto fused = fuse_pixels(o, frame, rgb, full_image, keep, used, object_T_camera,
                                     map_time, background_depth_m, false);
            if (!fused) return fused.status();
        }
        if (r.visible && !used.empty() && (r.tracked || r.pixels == 0)) {
            // Where the frame sees through the map, the object is not (it moved away, or the
            // map took in something that was not it). Not while it claims pixels that tracking
            // failed on: the map would be carved at a wrong pose. Pixels of persons and
            // unknown movers in front prove nothing either way; they are nearer, never
            // "through".
            // Untracked, its pose is a guess: the unstable surfels go, the model stays (for
            // the outputs, and to be found again).
            auto carved = o.map.carve(part, cv::Mat(), object_T_camera, map_time, !r.tracked);
            if (!carved) return carved.status();
        }
        if (r.tracked && !used.empty() && config_.refine_first_frames > 0 && !o.early_refined) {
            if (o.frames_tracked < static_cast<uint64_t>(config_.refine_after_frames)) {
                keep_early_view(o, part, of->object_ids(used), world_T_camera);
            } else {
                DF_RETURN_IF_ERROR(refine_early_poses(o, map_time));
            }
        }
        counters_.surfels_rejected_by_capacity += o.map.map().total_rejected_by_capacity() - before;
        r.surfels = o.map.map().size();
        if (frame_number - o.last_seen_frame >=
                static_cast<uint64_t>(config_.retire_after_frames) ||
            o.map.map().size() == 0) {
            o.state = ObjectState::kRetired;
            r.state = ObjectState::kRetired;
            ++counters_.retired;
        }
    }
    for (const dynamics::InstanceInfo* row :
         update_candidates(instances, of->association, frame_number, frame.levels[0].depth_m,
                           background_depth_m)) {
        DF_RETURN_IF_ERROR(create(frame, rgb, full_image, instances, *row, world_T_camera, map_time,
                                  frame_number, background_depth_m, of));
    }
    return Status::ok();
}

}  // namespace df::objects
