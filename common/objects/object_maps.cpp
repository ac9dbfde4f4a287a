#include "objects/object_maps.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "objects/object_maps_detail.hpp"
#include "slam/pose.hpp"

namespace df::objects {
namespace {

/// CV_8UC1: 255 where `labels` is not `id` (the pixels left out when tracking or fusing `id`).
cv::Mat all_but(const cv::Mat& labels, uint16_t id) { return labels != id; }

/// Where the map's surfel centres project at object_T_camera (level-0 pixels), grown by a margin
/// for the discs' extent and the motion still to be tracked; empty when none is in front.
cv::Rect projected_box(const map::SurfelMap& map, const Eigen::Isometry3d& object_T_camera,
                       const io::Intrinsics& k, cv::Size size) {
    const Eigen::Isometry3f camera_T_object = object_T_camera.inverse().cast<float>();
    float u0 = 1e9f, v0 = 1e9f, u1 = -1e9f, v1 = -1e9f;
    for (const map::Surfel& s : map.surfels()) {
        const Eigen::Vector3f p = camera_T_object * s.position;
        if (!(p.z() > 0.05f)) continue;
        const float u = static_cast<float>(k.fx) * p.x() / p.z() + static_cast<float>(k.cx);
        const float v = static_cast<float>(k.fy) * p.y() / p.z() + static_cast<float>(k.cy);
        u0 = std::min(u0, u);
        u1 = std::max(u1, u);
        v0 = std::min(v0, v);
        v1 = std::max(v1, v);
    }
    if (u1 < u0) return {};
    const float mu = 16.f + 0.15f * (u1 - u0), mv = 16.f + 0.15f * (v1 - v0);
    const cv::Rect box(
        cv::Point(static_cast<int>(std::floor(u0 - mu)), static_cast<int>(std::floor(v0 - mv))),
        cv::Point(static_cast<int>(std::ceil(u1 + mu)), static_cast<int>(std::ceil(v1 + mv))));
    return box & cv::Rect(0, 0, size.width, size.height);
}

}  // namespace

namespace detail {

bool mean_vertex(const slam::FrameLevel& level, const cv::Mat& mask, Eigen::Vector3d* out,
                 const cv::Mat& vertex) {
    const cv::Mat& vertices = vertex.empty() ? level.vertex : vertex;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int v = 0; v < level.height(); ++v) {
        const uint8_t* m = mask.ptr<uint8_t>(v);
        const cv::Vec3f* p = vertices.ptr<cv::Vec3f>(v);
        for (int u = 0; u < level.width(); ++u) {
            if (m[u] == 0 || !slam::is_valid_vertex(p[u])) continue;
            sum += Eigen::Vector3d(p[u][0], p[u][1], p[u][2]);
            ++n;
        }
    }
    if (n == 0) return false;
    *out = sum / n;
    return true;
}

}  // namespace detail

std::string validate(const ObjectMapsConfig& c) { return params::check(c); }

const char* to_string(ObjectState state) {
    switch (state) {
        case ObjectState::kActive:
            return "active";
        case ObjectState::kRetired:
            return "retired";
    }
    return "?";
}

ObjectMaps::ObjectMaps(const ObjectMapsConfig& config, const slam::TrackingConfig& tracking,
                       const map::SurfelMapConfig& map, const map::PredictionConfig& prediction,
                       const slam::PreprocessConfig& preprocess)
    : config_(config),
      tracking_(tracking),
      map_config_(map),
      prediction_(prediction),
      preprocess_(preprocess) {
    tracking_.min_inliers = config.min_inliers;
    tracking_.inlier_residual_m = config.inlier_residual_m;
    tracking_.min_level_correspondences = config.min_level_correspondences;
    rough_tracking_ = tracking_;
    rough_tracking_.min_level_correspondences = 0;
    map_config_.max_surfels = config.max_surfels;
    map_config_.unstable_max_unseen_frames = config.unstable_max_unseen_frames;
    // Every surfel of a small map counts: the object's model is rendered whole.
    prediction_.min_confidence = 0.f;
}

int ObjectMaps::live_count() const {
    return static_cast<int>(std::count_if(objects_.begin(), objects_.end(), [](const ObjectMap& o) {
        return o.state == ObjectState::kActive;
    }));
}

ObjectExtent ObjectMaps::extent_of(const ObjectMap& object) {
    ObjectExtent e;
    const auto& surfels = object.map.map().surfels();
    if (surfels.empty()) return e;
    for (const map::Surfel& s : surfels) e.centroid += s.position.cast<double>();
    e.centroid /= static_cast<double>(surfels.size());
    double sum = 0;
    for (const map::Surfel& s : surfels)
        sum += (s.position.cast<double>() - e.centroid).squaredNorm();
    e.radius_m = std::sqrt(sum / static_cast<double>(surfels.size()));
    return e;
}

Eigen::Vector3d ObjectMaps::centroid_in_world(const ObjectMap& object) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const auto& surfels = object.map.map().surfels();
    for (const map::Surfel& s : surfels) sum += s.position.cast<double>();
    const Eigen::Vector3d local = surfels.empty() ? sum : Eigen::Vector3d(sum / surfels.size());
    return object.map.world_T_map() * local;
}

namespace {
/// Lost frames over which a reported object's guess keeps moving by its last motion; after
/// that its guess stays where it was tracked last.
constexpr int kMaxHeldFrames = 10;
}  // namespace

Eigen::Isometry3d ObjectMap::predicted_pose() const {
    Eigen::Isometry3d pose = map.world_T_map();
    for (int k = 0; k <= std::min(frames_held, kMaxHeldFrames); ++k) pose = pose * body_motion;
    return slam::orthonormalized(pose);
}

Result<ObjectFrame> ObjectMaps::predict_and_associate(const slam::Frame& frame,
                                                      const dynamics::LabelImage& instances,
                                                      const Eigen::Isometry3d& world_T_camera_guess,
                                                      int map_time,
                                                      const cv::Mat& background_depth_m) {
    ObjectFrame out;
    out.world_T_camera_guess = world_T_camera_guess;
    const slam::FrameLevel& level = frame.levels[0];
    std::vector<ObjectView> views;
    for (size_t i = 0; i < objects_.size(); ++i) {
        ObjectMap& o = objects_[i];
        if (o.state != ObjectState::kActive) continue;
        const Eigen::Isometry3d world_T_object_guess = o.predicted_pose();
        const Eigen::Isometry3d object_T_camera =
            slam::orthonormalized(world_T_object_guess.inverse() * world_T_camera_guess);
        ObjectView view;
        view.class_id = o.class_id;
        view.depth_m = cv::Mat::zeros(level.depth_m.size(), CV_32F);
        cv::Rect roi;
        const slam::Frame part = slam::crop(
            frame,
            projected_box(o.map.map(), object_T_camera, level.intrinsics, level.depth_m.size()),
            &roi);
        if (!roi.empty()) {
            // Rendered in its part of the frame only: the cost follows the object's size.
            DF_RETURN_IF_ERROR(o.map.predict_model(part, object_T_camera, map_time, prediction_));
            cv::Mat z;
            cv::extractChannel(o.map.model().vertex, z, 2);
            z.copyTo(view.depth_m(roi));
        }
        views.push_back(std::move(view));
        out.live.push_back(i);
        out.rois.push_back(roi);
    }
    out.association =
        associate(instances, views, level.depth_m, config_.association, background_depth_m);
    out.object_ids = cv::Mat::zeros(level.depth_m.size(), CV_16UC1);
    for (size_t k = 0; k < out.live.size(); ++k) {
        const ObjectMap& o = objects_[out.live[k]];
        out.object_ids.setTo(o.id, out.association.view_labels == static_cast<uint16_t>(k + 1));
        ObjectReport r;
        r.id = o.id;
        r.class_id = o.class_id;
        r.visible = cv::countNonZero(views[k].depth_m) > 0;
        r.pixels = out.association.pixels_of_view[k];
        r.silhouette_pixels = out.association.silhouette_pixels_of_view[k];
        r.instance = out.association.instance_of_view[k];
        r.moving = o.mover.moving;
        r.settled = mover_settled(o.mover, config_);
        // Its last tracked pose (the map's own may have been moved on by dead reckoning).
        r.world_T_object =
            o.trajectory.empty() ? o.map.world_T_map() : io::isometry_of(o.trajectory.back());
        out.reports.push_back(r);
    }
    if (config_.association.grow_max_step_m > 0.f)
        grow_claims(instances, level.depth_m, background_depth_m, &out);
    return out;
}

void ObjectMaps::grow_claims(const dynamics::LabelImage& instances, const cv::Mat& depth_m,
                             const cv::Mat& background_depth_m, ObjectFrame* of) const {
    const Association& a = of->association;
    if (a.unmatched_rigid.empty() || instances.labels.size() != depth_m.size()) return;
    std::vector<uint8_t> open(65536, 0);
    for (uint16_t id : a.unmatched_rigid) open[id] = 1;
    // Every map that claims pixels grows, the detector's match or its silhouette's: room4's
    // suitcase map is tracked on its silhouette while YOLOv5s's box over its newly visible
    // part is another class's.
    // Per object id, its report's index + 1 (0: its claim does not grow).
    std::vector<uint16_t> grows(65536, 0);
    for (size_t k = 0; k < of->reports.size(); ++k) {
        const ObjectReport& r = of->reports[k];
        if (r.pixels > 0 && r.id > 0 && r.id < 65536)
            grows[static_cast<size_t>(r.id)] = static_cast<uint16_t>(k + 1);
    }
    const int w = depth_m.cols, h = depth_m.rows;
    std::vector<cv::Point> queue;
    for (int v = 0; v < h; ++v) {
        const uint16_t* ids = of->object_ids.ptr<uint16_t>(v);
        for (int u = 0; u < w; ++u)
            if (ids[u] != 0 && grows[ids[u]]) queue.emplace_back(u, v);
    }
    if (queue.empty()) return;
    const bool background =
        !background_depth_m.empty() && background_depth_m.size() == depth_m.size();
    const float step = config_.association.grow_max_step_m;
    const float step_per_m2 = config_.association.grow_max_step_per_m2;
    of->grown = cv::Mat::zeros(depth_m.size(), CV_8UC1);
    std::vector<int> added(of->reports.size(), 0);
    // Breadth first from every claimed pixel at once: where two claims meet, each keeps what it
    // reached first.
    for (size_t next = 0; next < queue.size(); ++next) {
        const cv::Point p = queue[next];
        const uint16_t id = of->object_ids.at<uint16_t>(p);
        const float dp = depth_m.at<float>(p);
        const cv::Point around[4] = {
            {p.x - 1, p.y}, {p.x + 1, p.y}, {p.x, p.y - 1}, {p.x, p.y + 1}};
        for (const cv::Point& q : around) {
            if (q.x < 0 || q.y < 0 || q.x >= w || q.y >= h) continue;
            if (of->object_ids.at<uint16_t>(q) != 0 || !open[instances.labels.at<uint16_t>(q)])
                continue;
            const float dq = depth_m.at<float>(q);
            if (!(dq > 0.f) || !(dp > 0.f) || std::abs(dq - dp) > step + step_per_m2 * dp * dp)
                continue;
            if (background &&
                agrees_with_background(dq, background_depth_m.at<float>(q), config_.association)) {
                continue;
            }
            of->object_ids.at<uint16_t>(q) = id;
            of->grown.at<uint8_t>(q) = 255;
            queue.push_back(q);
            ++added[grows[id] - 1];
        }
    }
    for (size_t k = 0; k < of->reports.size(); ++k) of->reports[k].pixels += added[k];
    for (size_t i = 0; i < a.unmatched_rigid.size(); ++i) {
        of->association.unmatched_claimed[i] =
            cv::countNonZero((instances.labels == a.unmatched_rigid[i]) & (of->object_ids != 0));
    }
}

Result<slam::TrackingResult> ObjectMaps::track_from(const slam::Frame& frame, ObjectMap& o,
                                                    const Eigen::Isometry3d& world_T_object_guess,
                                                    const Eigen::Isometry3d& world_T_camera,
                                                    const cv::Rect& instance_box,
                                                    const cv::Mat& object_ids, cv::Rect* roi,
                                                    int map_time, bool rough) {
    const Eigen::Isometry3d initial =
        slam::orthonormalized(world_T_object_guess.inverse() * world_T_camera);
    const slam::FrameLevel& level = frame.levels[0];
    const cv::Rect projected =
        projected_box(o.map.map(), initial, level.intrinsics, level.depth_m.size());
    const slam::Frame part = slam::crop(frame, projected | instance_box, roi);
    if (roi->empty()) return slam::TrackingResult{};
    // The model again at the camera's tracked pose, over the instance too (it may have moved
    // out of the first rendering's part of the frame).
    DF_RETURN_IF_ERROR(o.map.predict_model(part, initial, map_time, prediction_));
    const cv::Mat mask = all_but(object_ids(*roi), static_cast<uint16_t>(o.id));
    return o.map.track(part, initial, mask, rough ? rough_tracking_ : tracking_);
}

Status ObjectMaps::track(const slam::Frame& frame, const dynamics::LabelImage& instances,
                         const Eigen::Isometry3d& world_T_camera, int map_time, ObjectFrame* of) {
    const slam::FrameLevel& level = frame.levels[0];
    for (size_t k = 0; k < of->live.size(); ++k) {
        ObjectMap& o = objects_[of->live[k]];
        ObjectReport& r = of->reports[k];
        if (r.pixels < config_.min_track_pixels) continue;
        const Eigen::Isometry3d guess = o.predicted_pose();
        const cv::Mat instance =
            r.instance != 0 ? cv::Mat(instances.labels == r.instance) : cv::Mat();
        const cv::Rect instance_box = instance.empty() ? cv::Rect() : cv::boundingRect(instance);
        auto result = track_from(frame, o, guess, world_T_camera, instance_box, of->object_ids,
                                 &of->rois[k], map_time);
        if (!result) return result.status();
        // Not tracked on the previous frame, its guess is dead reckoning over the gap.
        const bool reacquiring =
            o.trajectory.empty() || o.trajectory.back().stamp_s != previous_stamp_s_;
        if (!instance.empty() && o.frames_held > 0) {
            // Dead reckoning overshoots an object that stopped while it was lost: try the pose
            // it was held at as well.
            cv::Rect held_roi;
            auto held = track_from(frame, o, o.map.world_T_map(), world_T_camera, instance_box,
                                   of->object_ids, &held_roi, map_time);
            if (!held) return held.status();
            if (held->state == slam::TrackingState::kOk &&
                (result->state != slam::TrackingState::kOk || held->inliers > result->inliers)) {
                result = held;
                of->rois[k] = held_roi;
            }
        }
        if (!instance.empty() && (result->state != slam::TrackingState::kOk || reacquiring)) {
            // The detector sees it where the guess does not put it (it turned or sped up), or
            // the guess is old: start again with the map's visible centroid moved onto the
            // instance's, and keep what agrees with more of the frame.
            Eigen::Vector3d seen, rendered;
            cv::Mat model_valid;
            cv::extractChannel(o.map.model().vertex, model_valid, 2);
            cv::Rect used;
            const slam::Frame part = slam::crop(frame, of->rois[k], &used);
            if (!used.empty() && detail::mean_vertex(level, instance, &seen) &&
                detail::mean_vertex(part.levels[0], model_valid > 0.f, &rendered,
                                    o.map.model().vertex)) {
                const Eigen::Vector3d shift = world_T_camera.linear() * (seen - rendered);
                Eigen::Isometry3d moved = guess;
                moved.pretranslate(shift);
                cv::Rect retry_roi;
                auto retry = track_from(frame, o, moved, world_T_camera, instance_box,
                                        of->object_ids, &retry_roi, map_time, /*rough=*/true);
                if (!retry) return retry.status();
                if (retry->state == slam::TrackingState::kOk &&
                    (result->state != slam::TrackingState::kOk ||
                     retry->inliers > result->inliers)) {
                    result = retry;
                    of->rois[k] = retry_roi;
                }
            }
        }
        r.tracking = *result;
        o.map.set_last_tracking(*result);
        if (result->state != slam::TrackingState::kOk) {
            // The output keeps its last tracked pose. A map the detector no longer reports
            // is moved on by its last motion (it may be there, unseen); one it reports stays
            // where it was tracked last, so the detection keeps matching it.
            if (instance.empty()) {
                o.map.set_world_T_map(guess);
                o.frames_held = 0;
            } else {
                ++o.frames_held;
            }
            if (++o.frames_lost > 3 && (instance.empty() || o.frames_held > kMaxHeldFrames)) {
                o.body_motion = Eigen::Isometry3d::Identity();
                o.frames_held = 0;
            }
            continue;
        }
        const Eigen::Isometry3d world_T_object =
            slam::orthonormalized(world_T_camera * result->world_T_camera.inverse());
        const Eigen::Isometry3d previous = o.map.world_T_map();
        o.body_motion = slam::orthonormalized(previous.inverse() * world_T_object);
        if (o.frames_lost > 0) o.body_motion = Eigen::Isometry3d::Identity();
        o.frames_lost = 0;
        o.frames_held = 0;
        o.map.set_world_T_map(world_T_object);
        o.trajectory.push_back(io::stamped_pose(frame.sensor_ns, world_T_object));
        ++o.frames_tracked;
        r.tracked = true;
        r.world_T_object = world_T_object;
        const ObjectExtent extent = extent_of(o);
        const double depth_m = (world_T_camera.inverse() * (world_T_object * extent.centroid)).z();
        r.mover_changed = update_mover(&o.mover, world_T_object, extent, depth_m, config_);
        r.moving = o.mover.moving;
        r.settled = mover_settled(o.mover, config_);
    }
    previous_stamp_s_ = io::stamped_pose(frame.sensor_ns, Eigen::Isometry3d::Identity()).stamp_s;
    return Status::ok();
}

namespace {

/// Views refined per frame once an object is due: the work is spread so that no frame pays for
/// all of them (30 views at once cost one room4 frame about 40 ms per object).
constexpr size_t kRefinedViewsPerFrame = 4;
/// The most bytes of early views an object keeps (a crop of 100x70 processing pixels takes about
/// 0.5 MB; an object filling a 320x240 frame about 6 MB).
constexpr size_t kMaxEarlyViewBytes = size_t{48} << 20;

size_t bytes_of(const slam::Frame& frame) {
    size_t n = 0;
    for (const slam::FrameLevel& l : frame.levels) {
        for (const cv::Mat* m : {&l.depth_m, &l.smoothed_depth_m, &l.vertex, &l.smoothed_vertex,
                                 &l.normal, &l.intensity, &l.grad_x, &l.grad_y}) {
            n += m->total() * m->elemSize();
        }
    }
    return n;
}

slam::Frame deep_copy(const slam::Frame& frame) {
    slam::Frame out = frame;
    for (slam::FrameLevel& l : out.levels) {
        for (cv::Mat* m : {&l.depth_m, &l.smoothed_depth_m, &l.vertex, &l.smoothed_vertex,
                           &l.normal, &l.intensity, &l.grad_x, &l.grad_y}) {
            *m = m->clone();
        }
    }
    return out;
}

}  // namespace

void ObjectMaps::keep_early_view(ObjectMap& o, const slam::Frame& part, const cv::Mat& object_ids,
                                 const Eigen::Isometry3d& world_T_camera) {
    if (o.early_refined || o.trajectory.empty() ||
        o.early_views.size() >= static_cast<size_t>(config_.refine_first_frames)) {
        return;
    }
    size_t kept = bytes_of(part);
    for (const ObjectMap::EarlyView& v : o.early_views) kept += bytes_of(v.part);
    if (kept > kMaxEarlyViewBytes) return;
    ObjectMap::EarlyView view;
    view.part = deep_copy(part);
    view.left_out = all_but(object_ids, static_cast<uint16_t>(o.id));
    view.world_T_camera = world_T_camera;
    view.trajectory_index = o.trajectory.size() - 1;
    o.early_views.push_back(std::move(view));
}

Status ObjectMaps::refine_early_poses(ObjectMap& o, int map_time) {
    const size_t n = std::min(kRefinedViewsPerFrame, o.early_views.size());
    std::vector<ObjectMap::EarlyView> views(std::make_move_iterator(o.early_views.begin()),
                                            std::make_move_iterator(o.early_views.begin() + n));
    o.early_views.erase(o.early_views.begin(), o.early_views.begin() + n);
    if (o.early_views.empty()) o.early_refined = true;
    for (ObjectMap::EarlyView& view : views) {
        if (view.trajectory_index >= o.trajectory.size()) continue;
        io::StampedPose& pose = o.trajectory[view.trajectory_index];
        const Eigen::Isometry3d tracked = io::isometry_of(pose);
        const Eigen::Isometry3d initial =
            slam::orthonormalized(tracked.inverse() * view.world_T_camera);
        DF_RETURN_IF_ERROR(o.map.predict_model(view.part, initial, map_time, prediction_));
        auto result = o.map.track(view.part, initial, view.left_out, tracking_);
        if (!result) return result.status();
        if (result->state != slam::TrackingState::kOk) continue;
        const Eigen::Isometry3d refined =
            slam::orthonormalized(view.world_T_camera * result->world_T_camera.inverse());
        if ((refined.translation() - tracked.translation()).norm() >
            config_.refine_max_correction_m) {
            continue;
        }
        const double stamp_s = pose.stamp_s;
        pose = io::stamped_pose(0, refined);
        pose.stamp_s = stamp_s;
        ++o.early_poses_refined;
    }
    return Status::ok();
}

}  // namespace df::objects
