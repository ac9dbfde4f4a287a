// ObjectMaps: the life of a map before it is tracked: candidates seen on consecutive frames,
// creation from a candidate's pixels, and revival or relocalisation of a map that lost its object
// (the per-frame tracking and fusion are in object_maps.cpp).
#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "objects/object_maps.hpp"
#include "objects/object_maps_detail.hpp"
#include "slam/pose.hpp"

namespace df::objects {
namespace {

/// The bounding box of a mask's non-zero pixels, in float pixels.
cv::Rect2f box_of(const cv::Mat& mask) {
    const cv::Rect r = cv::boundingRect(mask);
    return cv::Rect2f(static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.width),
                      static_cast<float>(r.height));
}

}  // namespace

std::vector<const dynamics::InstanceInfo*> ObjectMaps::update_candidates(
    const dynamics::LabelImage& instances, const Association& association, uint64_t frame_number,
    const cv::Mat& depth_m, const cv::Mat& background_depth_m) {
    std::vector<const dynamics::InstanceInfo*> ready;
    std::vector<Candidate> next;
    for (size_t i = 0; i < association.unmatched_rigid.size(); ++i) {
        const dynamics::InstanceInfo* row = instances.find(association.unmatched_rigid[i]);
        if (row == nullptr || row->pixels < config_.min_create_pixels) continue;
        // Mostly inside a known object's silhouette: that object, named otherwise.
        if (2 * association.unmatched_claimed[i] > row->pixels) continue;
        // Mostly explained by the static map: furniture that stood still since it was mapped
        // with the room. It needs no map of its own (it would have next to nothing to fuse).
        if (2 * cv::countNonZero(fusable(instances, row->id, depth_m, background_depth_m)) <
            row->pixels)
            continue;
        const cv::Rect2f box =
            row->box.area() > 0.f ? row->box : box_of(instances.labels == row->id);
        Candidate c{row->class_id, row->score, box, 1, frame_number};
        for (const Candidate& old : candidates_) {
            if (old.class_id == row->class_id && old.last_frame + 1 == frame_number &&
                box_iou(old.box, box) >= config_.candidate_min_iou) {
                c.sightings = old.sightings + 1;
                c.score = std::max(c.score, old.score);
                break;
            }
        }
        if (c.sightings >= config_.create_after_frames) {
            ready.push_back(row);
        } else {
            next.push_back(c);
        }
    }
    candidates_ = std::move(next);
    return ready;
}

Status ObjectMaps::create(const slam::Frame& frame, const cv::Mat& rgb,
                          const io::RgbdImage& full_image, const dynamics::LabelImage& instances,
                          const dynamics::InstanceInfo& row,
                          const Eigen::Isometry3d& world_T_camera, int map_time,
                          uint64_t frame_number, const cv::Mat& background_depth_m,
                          ObjectFrame* of) {
    const slam::FrameLevel& level = frame.levels[0];
    // Its pixels: the instance's that may be fused, less any already claimed by a map.
    const cv::Mat pixels =
        fusable(instances, row.id, level.depth_m, background_depth_m) & (of->object_ids == 0);
    Eigen::Vector3d centroid_camera;
    if (!detail::mean_vertex(level, pixels, &centroid_camera)) return Status::ok();
    const Eigen::Vector3d centroid = world_T_camera * centroid_camera;

    // A retired map of its class near it: the object came back.
    ObjectMap* object = nullptr;
    for (ObjectMap& o : objects_) {
        if (o.state != ObjectState::kRetired || o.class_id != row.class_id) continue;
        if ((centroid_in_world(o) - centroid).norm() <= config_.revive_max_distance_m) {
            object = &o;
            break;
        }
    }
    Eigen::Isometry3d relocalised_pose = Eigen::Isometry3d::Identity();
    bool relocalised = false;
    if (object == nullptr && config_.relocalise_any_class) {
        DF_RETURN_IF_ERROR(relocalise(frame, pixels, centroid, world_T_camera, map_time, *of,
                                      &object, &relocalised_pose));
        relocalised = object != nullptr;
    }
    if (object == nullptr && live_count() >= config_.max_objects) {
        ++counters_.refused_by_cap;
        return Status::ok();
    }
    ObjectReport r;
    r.created = true;
    r.class_id = row.class_id;
    r.instance = row.id;
    r.visible = true;
    if (object != nullptr) {
        // Moved while out of view: shift it so its centroid sits on what is seen now (the
        // next frame's tracking refines it), or put it where relocalisation tracked it.
        Eigen::Isometry3d pose = object->map.world_T_map();
        pose.pretranslate(centroid - centroid_in_world(*object));
        if (relocalised) pose = relocalised_pose;
        object->map.set_world_T_map(pose);
        object->state = ObjectState::kActive;
        object->body_motion = Eigen::Isometry3d::Identity();
        object->frames_lost = 0;
        object->frames_held = 0;
        object->last_seen_frame = frame_number;
        ++counters_.revived;
        r.id = object->id;
        r.class_id = object->class_id;
        r.world_T_object = pose;
        r.surfels = object->map.map().size();
        if (relocalised) {
            object->trajectory.push_back(io::stamped_pose(frame.sensor_ns, pose));
            ++object->frames_tracked;
            of->object_ids.setTo(object->id, pixels);
            r.pixels = cv::countNonZero(pixels);
            r.tracked = true;
        }
        // A live map (relocalised) already has this frame's report: it is replaced.
        const auto same = std::find_if(of->reports.begin(), of->reports.end(),
                                       [&](const ObjectReport& x) { return x.id == object->id; });
        if (same != of->reports.end()) {
            *same = r;
        } else {
            of->reports.push_back(r);
        }
        return Status::ok();
    }
    ObjectMap o(next_id_++, map_config_);
    o.class_id = row.class_id;
    o.score = row.score;
    o.first_frame = o.last_seen_frame = frame_number;
    Eigen::Isometry3d world_T_object = Eigen::Isometry3d::Identity();
    world_T_object.translation() = centroid;
    o.map.set_world_T_map(world_T_object);
    const Eigen::Isometry3d object_T_camera = world_T_object.inverse() * world_T_camera;
    auto fused = fuse_pixels(o, frame, rgb, full_image, pixels,
                             cv::Rect(cv::Point(0, 0), level.depth_m.size()), object_T_camera,
                             map_time, background_depth_m, true);
    if (!fused) return fused.status();
    o.trajectory.push_back(io::stamped_pose(frame.sensor_ns, world_T_object));
    ++o.frames_tracked;
    of->object_ids.setTo(o.id, pixels);
    if (config_.refine_first_frames > 0) {
        // The creation frame's pose is the object frame's first pose: refined with the rest.
        const cv::Rect box = cv::boundingRect(pixels);
        cv::Rect used;
        const slam::Frame part = slam::crop(frame, box + cv::Size(16, 16) - cv::Point(8, 8), &used);
        if (!used.empty()) keep_early_view(o, part, of->object_ids(used), world_T_camera);
    }
    r.id = o.id;
    r.pixels = cv::countNonZero(pixels);
    r.tracked = true;
    r.world_T_object = world_T_object;
    r.surfels = o.map.map().size();
    of->reports.push_back(r);
    objects_.push_back(std::move(o));
    ++counters_.created;
    return Status::ok();
}

Status ObjectMaps::relocalise(const slam::Frame& frame, const cv::Mat& pixels,
                              const Eigen::Vector3d& centroid,
                              const Eigen::Isometry3d& world_T_camera, int map_time,
                              const ObjectFrame& of, ObjectMap** found,
                              Eigen::Isometry3d* world_T_object) {
    *found = nullptr;
    const cv::Rect box = cv::boundingRect(pixels);
    for (size_t i = 0; i < objects_.size(); ++i) {
        ObjectMap& o = objects_[i];
        if (o.map.map().size() == 0) continue;
        bool lost_its_object = o.state == ObjectState::kRetired;
        if (!lost_its_object) {
            const auto k = std::find(of.live.begin(), of.live.end(), i);
            lost_its_object =
                k != of.live.end() && of.reports[static_cast<size_t>(k - of.live.begin())].pixels == 0;
        }
        if (!lost_its_object) continue;
        // From where it is now (moved on by its last motion while unseen) and from where it
        // was last tracked, whichever is near.
        std::vector<Eigen::Isometry3d> starts{o.map.world_T_map()};
        if (!o.trajectory.empty()) starts.push_back(io::isometry_of(o.trajectory.back()));
        const Eigen::Vector3d local = o.map.world_T_map().inverse() * centroid_in_world(o);
        for (const Eigen::Isometry3d& start : starts) {
            const Eigen::Vector3d c = start * local;
            if ((c - centroid).norm() > config_.relocalise_max_distance_m) continue;
            Eigen::Isometry3d moved = start;
            moved.pretranslate(centroid - c);
            cv::Mat ids = of.object_ids.clone();
            ids.setTo(o.id, pixels);
            cv::Rect roi;
            auto result = track_from(frame, o, moved, world_T_camera, box, ids, &roi,
                                     map_time, /*rough=*/true);
            if (!result) return result.status();
            if (result->state != slam::TrackingState::kOk) {
                // The centroids of the whole model and of its visible part differ, so the
                // shifted guess is rough: once more from where Gauss-Newton went; it must
                // then pass every check (how far it moves included).
                const Eigen::Isometry3d again =
                    slam::orthonormalized(world_T_camera * result->estimate.inverse());
                result = track_from(frame, o, again, world_T_camera, box, ids, &roi, map_time,
                                    /*rough=*/true);
                if (!result) return result.status();
            }
            if (result->state != slam::TrackingState::kOk) continue;
            *world_T_object =
                slam::orthonormalized(world_T_camera * result->world_T_camera.inverse());
            *found = &o;
            return Status::ok();
        }
    }
    return Status::ok();
}

}  // namespace df::objects
