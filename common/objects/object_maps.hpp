#pragma once
/// Object maps (paper, Mapping and Tracking): every rigid object of a known class that the
/// detector keeps seeing gets a surfel map of its own, in its own frame, with its own pose in
/// the world, so it may move independently of the room and of the other objects. Each frame:
///   1. predict: every live map is rendered at the pose the camera and the object are expected
///      at (constant velocity), and the frame's rigid instances are associated with the
///      renderings (association.hpp): each map claims its instance's pixels and the pixels of
///      its silhouette whose depth agrees (it is seen even when the detector misses it);
///   2. track (once the camera's pose is known): each map with claimed pixels is tracked on
///      those pixels alone against its own rendering; world_T_object = world_T_camera *
///      camera_T_object. A map whose tracking fails keeps its last pose and says so;
///   3. map: tracked maps fuse their pixels; every map in view loses the surfels the frame sees
///      through (free-space violations: an object that left shrinks); an unmatched rigid
///      instance seen on enough consecutive frames, big enough, creates a map (or revives a
///      retired map of its class near it); maps unmatched for too long are retired (kept for
///      the outputs, no longer tracked).
/// DDS-free. SlamSystem orchestrates it around the static map (which is one MapInstance, as
/// each object map is).
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "dynamics/frame_segments.hpp"
#include "io/tum/trajectory.hpp"
#include "map/surfel_map.hpp"
#include "objects/association.hpp"
#include "objects/mover_evidence.hpp"
#include "params/slam_params.hpp"
#include "slam/frame.hpp"
#include "slam/map_instance.hpp"
#include "slam/tracker.hpp"

namespace df::objects {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Objects), and generated into params/slam_params.hpp.
using ObjectMapsConfig = params::slam::Objects;

std::string validate(const ObjectMapsConfig& config);

enum class ObjectState {
    kActive,   ///< rendered, associated and tracked every frame
    kRetired,  ///< unmatched too long: kept for the outputs
};
const char* to_string(ObjectState state);

/// One object map and its history.
struct ObjectMap {
    int id = 0;             ///< the object's id for the whole run (1, 2, ...)
    int class_id = -1;      ///< COCO index
    float score = 0.f;      ///< detection score of the instance that created it
    slam::MapInstance map;  ///< surfels in the object frame; world_T_map() = world_T_object
    ObjectState state = ObjectState::kActive;
    uint64_t first_frame = 0, last_seen_frame = 0;  ///< frames (SlamSystem's count)
    uint64_t frames_tracked = 0;
    int frames_lost = 0;  ///< consecutive frames its tracking failed
    /// world_T_object(t-2)^-1 world_T_object(t-1): the motion in the object's own frame, for
    /// the constant-velocity guess; identity after a failed tracking.
    Eigen::Isometry3d body_motion = Eigen::Isometry3d::Identity();
    /// Consecutive failed frames on which the detector still reported it: its pose is held
    /// where it was tracked last (so the detection keeps matching it) while the guess moves on
    /// by body_motion once per such frame (dead reckoning, up to kMaxHeldFrames).
    int frames_held = 0;
    std::vector<io::StampedPose> trajectory;  ///< world_T_object of the frames it was tracked
    /// Whether it moves against the static map (mover_evidence.hpp; config keep_until_moving).
    MoverEvidence mover;

    /// One of its first tracked frames, kept until its early poses are refined
    /// (config refine_first_frames): they were tracked against a model still being built.
    struct EarlyView {
        slam::Frame part;  ///< the tracked crop, a deep copy
        cv::Mat left_out;  ///< CV_8UC1 of the crop: non-zero where the pixel is not the object's
        Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();
        size_t trajectory_index = 0;
    };
    std::vector<EarlyView> early_views;
    bool early_refined = false;   ///< done, or restored from a checkpoint (views not kept)
    int early_poses_refined = 0;  ///< early poses the refinement replaced

    /// Where it should be this frame: its pose moved on by body_motion once, and once more per
    /// held frame.
    Eigen::Isometry3d predicted_pose() const;

    ObjectMap(int id_, const map::SurfelMapConfig& config) : id(id_), map(id_, config) {}
};

/// What happened to one object map in one frame.
struct ObjectReport {
    int id = 0;
    int class_id = -1;
    ObjectState state = ObjectState::kActive;
    bool created = false;           ///< made (or revived) this frame
    bool visible = false;           ///< its rendering showed in the frame
    int pixels = 0;                 ///< pixels it claimed (instance and silhouette)
    int silhouette_pixels = 0;      ///< of those, the ones only its rendering gave
    uint16_t instance = 0;          ///< the frame instance matched to it (0 none)
    bool tracked = false;           ///< tracking ran and passed its checks
    bool moving = false;            ///< a proven mover (mover_evidence.hpp), as of this frame
    bool mover_changed = false;     ///< it became a proven mover, or still again, this frame
    bool settled = false;           ///< a settled candidate (mover_settled), as of this frame
    slam::TrackingResult tracking;  ///< when tracking ran
    Eigen::Isometry3d world_T_object = Eigen::Isometry3d::Identity();
    size_t surfels = 0;
};

/// Counters over the run.
struct ObjectCounters {
    uint64_t created = 0, revived = 0, retired = 0;
    uint64_t refused_by_cap = 0;                ///< creations refused at max_objects
    uint64_t surfels_rejected_by_capacity = 0;  ///< over every map, at max_surfels
};

/// Everything of an object map a checkpoint keeps (its model is rendered afresh each frame).
struct ObjectMapState {
    int id = 0;
    int class_id = -1;
    float score = 0.f;
    ObjectState state = ObjectState::kActive;
    uint64_t first_frame = 0, last_seen_frame = 0, frames_tracked = 0;
    int frames_lost = 0;
    Eigen::Isometry3d world_T_object = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d body_motion = Eigen::Isometry3d::Identity();
    MoverEvidence mover;
    std::vector<io::StampedPose> trajectory;
    std::vector<map::Surfel> surfels;  ///< in the object's frame, in storage order
    uint64_t surfels_rejected_by_capacity = 0;
};

/// Every object map of a run and the counters, as a checkpoint keeps them. Candidates (rigid
/// instances not yet a map) are not kept: a resumed run sees them again.
struct ObjectMapsState {
    std::vector<ObjectMapState> objects;  ///< creation order
    ObjectCounters counters;
    int next_id = 1;
};

/// One frame's object pixels, from predict_and_associate() to map().
struct ObjectFrame {
    /// CV_16UC1 of the processing resolution: the object id that claims each pixel, 0 none.
    cv::Mat object_ids;
    /// Per live map (index into ObjectMaps::objects()), what association gave it.
    std::vector<size_t> live;    ///< indices of the live maps, in view order
    std::vector<cv::Rect> rois;  ///< per live map: its part of the frame (may be empty)
    Association association;     ///< views = live, in that order
    /// CV_8UC1 (or empty): the pixels of unmatched rigid instances a map's claim grew into
    /// (association.grow_max_step_m); they are fused into that map with its instance's.
    cv::Mat grown;
    std::vector<ObjectReport> reports;  ///< per live map, then per map created this frame
    Eigen::Isometry3d world_T_camera_guess = Eigen::Isometry3d::Identity();
};

class ObjectMaps {
  public:
    /// `tracking`: the static map's tracking thresholds (objects use them with min_inliers of
    /// `config`); `map`, `prediction`: the static map's surfel and rendering settings (objects
    /// use them with max_surfels of `config`).
    /// `preprocess`: the static map's preprocessing (objects fused at the sensor's resolution
    /// preprocess their part of it alike, its pixel sizes scaled to it).
    ObjectMaps(const ObjectMapsConfig& config, const slam::TrackingConfig& tracking,
               const map::SurfelMapConfig& map, const map::PredictionConfig& prediction,
               const slam::PreprocessConfig& preprocess);

    /// Step 1: renders the live maps at the camera guess (each map moved on by its own
    /// constant velocity) and associates them with the frame's instances (`instances`, at the
    /// frame's level-0 size). `map_time`: the surfel maps' frame counter.
    /// `background_depth_m`: the static map's rendered depth (CV_32F, may be empty), for
    /// association.hpp's rule that what the background explains stays the background's.
    Result<ObjectFrame> predict_and_associate(const slam::Frame& frame,
                                              const dynamics::LabelImage& instances,
                                              const Eigen::Isometry3d& world_T_camera_guess,
                                              int map_time, const cv::Mat& background_depth_m);

    /// Step 2: tracks every live map with enough pixels; `world_T_camera`: the frame's pose.
    /// Records the pose of each tracked map in its trajectory (stamp: the frame's).
    Status track(const slam::Frame& frame, const dynamics::LabelImage& instances,
                 const Eigen::Isometry3d& world_T_camera, int map_time, ObjectFrame* object_frame);

    /// Step 3: fusion of tracked maps, free-space carving of the maps in view, creation from
    /// `instances`' unmatched rigid instances, retirement. `frame_number`: SlamSystem's frame
    /// count; `rgb`: the frame's colour at level-0 size; `background_depth_m`: the static map's
    /// rendered depth at world_T_camera (may be empty): instance pixels it explains are not
    /// fused into an object (the floor at its feet). `full_image`: the frame at the sensor's
    /// resolution (an integer multiple of level 0's size), which objects are fused from when
    /// config.fuse_full_resolution is on; empty (or not such a multiple): fused from `frame`.
    Status map(const slam::Frame& frame, const cv::Mat& rgb, const io::RgbdImage& full_image,
               const dynamics::LabelImage& instances, const Eigen::Isometry3d& world_T_camera,
               int map_time, uint64_t frame_number, const cv::Mat& background_depth_m,
               ObjectFrame* object_frame);

    /// Every map made in the run, live and retired, in creation order.
    const std::vector<ObjectMap>& objects() const { return objects_; }
    const ObjectCounters& counters() const { return counters_; }
    const ObjectMapsConfig& config() const { return config_; }

    /// The maps and counters, for a checkpoint.
    ObjectMapsState state() const;
    /// Replaces every map and counter with `state`'s (a checkpoint's). kInvalidArgument naming
    /// the object when an id repeats, a pose is not finite or the surfels do not fit max_surfels.
    Status restore(ObjectMapsState state);

  private:
    /// A rigid instance seen on consecutive frames, not yet a map.
    struct Candidate {
        int class_id = -1;
        float score = 0.f;
        cv::Rect2f box;
        int sightings = 0;
        uint64_t last_frame = 0;
    };

    int live_count() const;
    /// Tracks `o` in its part of the frame (its rendering at the guess, and `instance_box`)
    /// starting from world_T_object_guess; the part used goes to *roi. A `rough` guess (a
    /// centroid shift, a relocalisation) lets every pyramid level step, whatever its
    /// correspondences: the coarse levels' wide basin is what such a guess needs.
    Result<slam::TrackingResult> track_from(const slam::Frame& frame, ObjectMap& o,
                                            const Eigen::Isometry3d& world_T_object_guess,
                                            const Eigen::Isometry3d& world_T_camera,
                                            const cv::Rect& instance_box, const cv::Mat& object_ids,
                                            cv::Rect* roi, int map_time, bool rough = false);
    /// A map that lost its object (retired, or live and claiming nothing this frame) within
    /// relocalise_max_distance_m of `centroid` that, moved so the centroids agree, tracks onto
    /// `pixels` (CV_8UC1 of level 0): *found is it and *world_T_object its tracked pose; else
    /// *found is nullptr.
    Status relocalise(const slam::Frame& frame, const cv::Mat& pixels,
                      const Eigen::Vector3d& centroid, const Eigen::Isometry3d& world_T_camera,
                      int map_time, const ObjectFrame& object_frame, ObjectMap** found,
                      Eigen::Isometry3d* world_T_object);
    /// The map's centroid and radius in its own frame (mover_evidence.hpp).
    static ObjectExtent extent_of(const ObjectMap& object);
    /// The map's centroid in the world (mean surfel position).
    Eigen::Vector3d centroid_in_world(const ObjectMap& object) const;
    /// Creates (or revives) a map from instance `id`'s pixels of this frame.
    Status create(const slam::Frame& frame, const cv::Mat& rgb, const io::RgbdImage& full_image,
                  const dynamics::LabelImage& instances, const dynamics::InstanceInfo& row,
                  const Eigen::Isometry3d& world_T_camera, int map_time, uint64_t frame_number,
                  const cv::Mat& background_depth_m, ObjectFrame* object_frame);
    /// Fuses the pixels of `keep` (CV_8UC1 of level 0's size, non-zero = fuse) inside `roi`
    /// (level-0 pixels) into `o` with the camera at object_T_camera: from `full_image` (see
    /// map()) when fuse_full_resolution is on and `create_surfels`, else from `frame` and
    /// `rgb`. `create_surfels` false (a silhouette's confirmation): only the surfels already
    /// there are updated.
    Result<map::FusionStats> fuse_pixels(ObjectMap& o, const slam::Frame& frame, const cv::Mat& rgb,
                                         const io::RgbdImage& full_image, const cv::Mat& keep,
                                         const cv::Rect& roi,
                                         const Eigen::Isometry3d& object_T_camera, int map_time,
                                         const cv::Mat& background_depth_m, bool create_surfels);
    /// Keeps the crop `part` that `o` was tracked in this frame (and `object_ids` over it) while
    /// it is one of its first refine_first_frames tracked frames.
    void keep_early_view(ObjectMap& o, const slam::Frame& part, const cv::Mat& object_ids,
                         const Eigen::Isometry3d& world_T_camera);
    /// Tracks the oldest few kept early views again against `o`'s model as it is now, replaces
    /// their trajectory poses where that passes (config refine_*) and frees them; called once
    /// per tracked frame from refine_after_frames on, until none is left.
    Status refine_early_poses(ObjectMap& o, int map_time);
    /// Grows the claims of the maps that claim pixels into adjacent pixels of unmatched
    /// rigid instances (association.grow_max_step_m); updates object_ids, grown, the reports'
    /// pixels and association.unmatched_claimed.
    void grow_claims(const dynamics::LabelImage& instances, const cv::Mat& depth_m,
                     const cv::Mat& background_depth_m, ObjectFrame* object_frame) const;
    /// CV_8UC1, 255 on the pixels of instance `id` to fuse: eroded, valid depth, and not
    /// explained by the background.
    cv::Mat fusable(const dynamics::LabelImage& instances, uint16_t id, const cv::Mat& depth_m,
                    const cv::Mat& background_depth_m) const;
    /// Updates the candidates with this frame's unmatched rigid instances (not those mostly
    /// inside a map's silhouette or mostly explained by the static map); returns the rows whose
    /// candidate is ready to become a map.
    std::vector<const dynamics::InstanceInfo*> update_candidates(
        const dynamics::LabelImage& instances, const Association& association,
        uint64_t frame_number, const cv::Mat& depth_m, const cv::Mat& background_depth_m);

    ObjectMapsConfig config_;
    slam::TrackingConfig tracking_;
    slam::TrackingConfig rough_tracking_;  ///< tracking_ with every level stepping
    map::SurfelMapConfig map_config_;
    map::PredictionConfig prediction_;
    slam::PreprocessConfig preprocess_;
    std::vector<ObjectMap> objects_;
    std::vector<Candidate> candidates_;
    ObjectCounters counters_;
    int next_id_ = 1;
    /// The stamp of the frame track() saw last (a map whose trajectory ends before it is
    /// re-acquired); not in a checkpoint: after a restore every map counts as re-acquired once.
    double previous_stamp_s_ = -1.0;
};

}  // namespace df::objects
