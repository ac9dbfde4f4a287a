#pragma once
/// The dense SLAM loop with the paper's dynamic handling of the static map: preprocess -> track
/// against the static map's model with the frame's object instances left out (stage 1) ->
/// motion segmentation of stage 1's residuals -> refine the pose with the whole invalid mask
/// left out (stage 2) -> fuse the valid pixels into the static map -> predict its model at the
/// new pose. DDS-free: the offline command and the SLAM service both drive it one image at a
/// time, with the frame's masks as a label image and a table (dynamics::FrameSegments).
///
/// The static map is one MapInstance; object maps (the next step) are more instances of it.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "dynamics/frame_segments.hpp"
#include "dynamics/instance_memory.hpp"
#include "dynamics/invalid_mask.hpp"
#include "dynamics/motion_segmentation.hpp"
#include "io/rgbd_image.hpp"
#include "io/tum/trajectory.hpp"
#include "map/surfel_map.hpp"
#include "objects/object_maps.hpp"
#include "slam/frame.hpp"
#include "slam/map_instance.hpp"
#include "slam/tracker.hpp"
#include "slam_system/system_config.hpp"

namespace df::slam {

/// Milliseconds spent in each stage of one frame (wall clock).
struct StageTimes {
    double preprocess_ms = 0, tracking_ms = 0, fusion_ms = 0, prediction_ms = 0, total_ms = 0;
    /// Parts of tracking_ms: stage 1, motion segmentation (residuals included), stage 2.
    double stage1_ms = 0, motion_ms = 0, stage2_ms = 0;
    /// Object maps: rendering and association, tracking, and fusion / creation / retirement.
    double objects_predict_ms = 0, objects_track_ms = 0, objects_map_ms = 0;
    /// ("preprocess", ms), ... in pipeline order, for timing log lines.
    std::vector<std::pair<std::string, double>> steps() const;
};

/// What one call of process() did.
struct FrameReport {
    uint64_t frame_number = 0;  ///< 0-based count of frames given to process()
    int64_t sensor_ns = 0;      ///< the image's stamp
    bool first = false;         ///< the frame that started the map (pose = initial pose)
    TrackingResult tracking;    ///< the pose used: stage 2's when it ran and held, else stage 1's
    TrackingResult stage1;      ///< against the static model, object instances left out
    TrackingResult stage2;      ///< refinement with the whole invalid mask left out
    bool stage2_ran = false;    ///< motion segmentation found movers, so stage 2 ran
    /// Motion segmentation of stage 1's residuals (mask empty when it did not run).
    dynamics::MotionResult motion;
    /// The invalid mask at the processing resolution (system.processing_downscale), as masks
    /// and as labels with their table; empty masks when nothing was left out.
    dynamics::InvalidMask invalid;
    /// Why the frame's segments were not used ("" when they were, or there were none): they
    /// did not fit the image (wrong size, unknown id). The frame is tracked without them.
    std::string segments_error;
    Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();  ///< as reported
    bool fused = false;
    map::FusionStats fusion;
    /// What each object map did this frame: the live maps, then those created or revived.
    std::vector<objects::ObjectReport> objects;
    /// CV_16UC1 at the processing resolution: the object map id claiming each pixel, 0 none
    /// (empty when object maps are off).
    cv::Mat object_ids;
    /// The frame's object instances as used, at the processing resolution: its own, or (its
    /// detections not fresh) the last frame's carried forward, each row with its age.
    dynamics::LabelImage instances;
    int detections_age = 0;  ///< the frame's segments' detections_age
    int carried = 0;         ///< instances carried forward into this frame
    /// Why the frame was tracked and fused with only its persons left out ("" when it was not):
    /// its invalid mask would have left out too much, or too little static model (guards).
    std::string guard;
    /// Why the static map was rebuilt from this frame ("" when it was not): it was empty, or the
    /// camera was lost too long. The trajectory starts a new segment here.
    std::string rebuilt;
    StageTimes times;
};

/// Everything a SlamSystem carries from frame to frame, besides its configuration and the
/// model (which restore() predicts again): what a checkpoint saves (slam_system/checkpoint.hpp).
struct SystemState {
    std::vector<map::Surfel> surfels;  ///< the static map, in storage order
    uint64_t surfels_rejected_by_capacity = 0;
    Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();  ///< the current pose
    Eigen::Isometry3d last_motion = Eigen::Isometry3d::Identity();     ///< previous_T_current
    std::vector<io::StampedPose> trajectory;
    uint64_t frames = 0;
    uint64_t lost_frames = 0;
    int map_time = 0;
    bool started = false;
    bool lost = false;
    int input_width = 0;  ///< of the first frame (0 before it)
    int input_height = 0;
    objects::ObjectMapsState objects;  ///< every object map, live and retired
};

/// What the guards against self-harm did over a run (docs/dynamics.md, "Guards").
struct GuardCounters {
    uint64_t frames_guarded = 0;  ///< frames tracked and fused with only persons left out
    uint64_t rebuilds = 0;        ///< times the static map was rebuilt
    /// The frame numbers (0-based) each trajectory segment after the first starts at.
    std::vector<uint64_t> segment_starts;
};

class SlamSystem {
  public:
    /// Fails (kInvalidArgument naming the field) when the configuration is not usable.
    static Result<SlamSystem> create(
        const SystemConfig& config,
        const Eigen::Isometry3d& initial_world_T_camera = Eigen::Isometry3d::Identity());

    /// A system that goes on from `state` (a checkpoint's). The model to track against is
    /// predicted from the restored map at the restored pose when the next image comes (its
    /// intrinsics are needed), so tracking goes on from the map, not from an empty model.
    /// kInvalidArgument for a bad configuration or a state whose pose is not finite.
    static Result<SlamSystem> restore(const SystemConfig& config, SystemState state);
    /// The state to checkpoint (copies the map).
    SystemState state() const;

    /// Processes the next image with the masks it comes with (`segments`, of the image's size;
    /// empty: none, motion segmentation alone). Segments that do not fit the image are not
    /// used (FrameReport::segments_error says why) and the frame is still tracked.
    /// kInvalidArgument for an unusable image (wrong type, size changed since the first frame,
    /// bad intrinsics); the system is unchanged then and the next good image goes on from the
    /// last pose.
    Result<FrameReport> process(const io::RgbdImage& image,
                                const dynamics::FrameSegments& segments = {});

    /// Poses of the frames tracked (state kOk, and the first), in order: the trajectory in TUM
    /// form (stamps from sensor_ns). Lost frames are left out (`lost_frames()` counts them).
    const std::vector<io::StampedPose>& trajectory() const { return trajectory_; }
    uint64_t frames() const { return frames_; }
    uint64_t lost_frames() const { return lost_frames_; }
    /// True when the last frame was lost.
    bool lost() const { return lost_; }
    const map::SurfelMap& static_map() const { return static_.map(); }
    /// Every object map of the run (live and retired) and the run's object counters.
    const objects::ObjectMaps& object_maps() const { return objects_; }
    const SystemConfig& config() const { return config_; }
    /// What the guards did so far.
    const GuardCounters& guards() const { return guards_; }
    /// The current pose (the last tracked one).
    const Eigen::Isometry3d& world_T_camera() const { return world_T_camera_; }
    /// The model the next frame is tracked against, and the pose it was predicted at.
    const ModelView& model() const { return static_.model(); }
    const Eigen::Isometry3d& world_T_model() const { return static_.map_T_model(); }

    /// Writes trajectory() as a TUM file.
    Status write_trajectory(const std::string& file) const;
    /// Object segments of an earlier frame that arrived after that frame was tracked (a
    /// detector slower than the camera, the service's segments deadline passed). When the frame
    /// is still in the motion history (motion.history_frames) and its instances are fresher
    /// than those propagation holds, they replace them: the next frames carry the detector's
    /// newest instances forward, aged by the frames since. A frame skipped to stay current
    /// stands in for the tracked frame nearest in time (within 50 ms). `sensor_ns`: its stamp;
    /// `objects` at the input size. Returns whether they were taken.
    bool take_late_instances(int64_t sensor_ns, const dynamics::LabelImage& objects);
    /// Writes the static map's stable surfels (all when stable_only is false) as binary PLY.
    Status write_map(const std::string& file, bool stable_only = true) const;

  private:
    /// One frame on its way through process().
    struct Input {
        io::RgbdImage image;               ///< at the processing resolution
        io::RgbdImage full;                ///< as it came (the sensor's resolution)
        dynamics::FrameSegments segments;  ///< at the processing resolution (checked)
        Frame frame;
        cv::Mat instance_ids;  ///< CV_16UC1, the instances left out (instance_labels)
        cv::Mat instances;     ///< CV_8UC1, instance_ids as a mask (255 = left out)
        cv::Mat rigid;         ///< CV_8UC1, the rigid instances this frame's segments hold
        /// CV_8UC1, the rigid instances as the frame came (before object maps or
        /// keep_until_moving kept any in the static map): what motion's history remembers as
        /// seen here as an object.
        cv::Mat detected_rigid;
        /// CV_8UC1 (or empty), pixels tracked against the static map but not fused into it:
        /// rigid instances the static map already explains (furniture) and, with
        /// objects.keep_until_moving, candidates not yet settled.
        cv::Mat explained;
        objects::ObjectFrame objects;  ///< the object maps' pixels of this frame
    };

    explicit SlamSystem(const SystemConfig& config, const Eigen::Isometry3d& initial);
    /// Checks and downscales the image and its segments, preprocesses the frame.
    Status prepare(const io::RgbdImage& image, const dynamics::FrameSegments& segments,
                   const std::string& where, Input* in, FrameReport* report) const;
    /// A frame without fresh detections gets the last frame's instances carried forward in
    /// place of its own (dynamics/instance_propagation.hpp); then the instances left out.
    void carry_instances(Input* in, FrameReport* report) const;
    /// Adds the rigid instances the memory holds and this frame's segments miss to the
    /// instances left out (one table row, class -1, kind rigid).
    void recall_instances(Input* in);
    /// Stores this frame's rigid instances in the memory, and its depth with its pose in the
    /// motion history (forgets both when tracking is lost).
    void remember(const Input& in);
    /// The initial guess of this frame's pose (constant velocity when configured).
    Eigen::Isometry3d pose_guess() const;
    /// Renders the object maps at `guess`, associates them with the frame's instances and
    /// leaves the pixels they claim out of the static map (as rigid instances).
    Status predict_objects(const Eigen::Isometry3d& guess, Input* in, FrameReport* report);
    /// With objects.keep_until_moving: the rigid instances not matched to a proven mover leave
    /// in->instance_ids (they stay in the static map's tracking, and in its fusion once their
    /// map settled; until then in->explained).
    void keep_unproven_in_static(Input* in) const;
    /// Adds `pixels` (CV_8UC1) to in->explained: tracked, not fused.
    static void hold_out_of_fusion(const cv::Mat& pixels, Input* in);
    /// CV_8UC1, 255 on the pixels of in.instance_ids that belong to non-rigid instances.
    static cv::Mat non_rigid_mask(const Input& in);
    /// Why the frame's invalid mask is not to be trusted ("" when it is): it leaves out more
    /// than dynamics.guard_max_left_out_fraction of the frame's depth, or the static model
    /// outside it covers less than dynamics.guard_min_model_fraction of the frame.
    std::string guard_reason(const Input& in, const dynamics::InvalidMask& invalid) const;
    /// Tracks the frame with only its non-rigid instances left out (from `guess`) and makes
    /// that the invalid mask for tracking and fusion.
    Status track_guarded(const Input& in, const Eigen::Isometry3d& guess, const cv::Mat& residual,
                         FrameReport* report);
    /// Starts a new static map from this frame, at the last tracked pose, when the map is
    /// empty or the camera was lost dynamics.rebuild_after_lost_frames frames in a row.
    void rebuild_if_needed(FrameReport* report);
    /// Adds in.explained (furniture the static map holds) to the pixels left out of fusion.
    static void keep_explained_out_of_fusion(const Input& in, dynamics::InvalidMask* invalid);
    /// Stage 1, motion segmentation, stage 2; fills report->tracking and report->invalid.
    Status track_static(const Input& in, const Eigen::Isometry3d& guess, FrameReport* report);
    /// Moves the camera to the tracked pose (or counts the frame lost) and logs it.
    void update_pose(int64_t sensor_ns, FrameReport* report);
    /// Fuses the frame's valid pixels into the static map and predicts the next model.
    Status map_static(const Input& in, FrameReport* report);
    /// The static model's depth (CV_32F metres, 0 none; empty before the first model).
    cv::Mat static_depth() const;
    /// Tracks, fuses, creates and retires the object maps (the camera's pose is known).
    Status map_objects(Input* in, FrameReport* report);
    /// The model the next frame is tracked against: the map predicted at world_T_camera_
    /// (confident surfels only once bootstrapped). reuse_association: out of fusion's rendering
    /// of this frame when there is one (system.model_from_association), else rendered.
    Status predict_model(const Frame& frame, FrameReport* report, bool reuse_association = false);
    /// How the model is rendered at map_time_ (confident surfels only once bootstrapped).
    map::PredictionConfig model_prediction() const;

    SystemConfig config_;
    MapInstance static_;
    objects::ObjectMaps objects_;
    Eigen::Isometry3d world_T_camera_;
    Eigen::Isometry3d last_motion_ = Eigen::Isometry3d::Identity();  ///< previous_T_current
    cv::Mat previous_motion_;                    ///< the last frame's motion mask (carried forward)
    dynamics::InstanceMemory memory_;            ///< rigid instances of the last frames
    dynamics::InstancePropagation propagation_;  ///< the last frame's instances
    /// One tracked frame as motion segmentation's free-space evidence remembers it.
    struct HistoryFrame {
        cv::Mat depth_m;  ///< level 0
        /// level 0 up to motion.seen_through_max_depth_m (beyond preprocessing's cut): what the
        /// frame saw far away still tells free space (empty: depth_m is that)
        cv::Mat far_depth_m;
        cv::Mat rigid;  ///< its rigid instances (object maps' claims included)
        Eigen::Isometry3d world_T_camera;
        int64_t sensor_ns = 0;
        uint64_t frame_number = 0;
    };
    /// The last motion.history_frames tracked frames, oldest first.
    std::deque<HistoryFrame> history_;
    std::vector<io::StampedPose> trajectory_;
    uint64_t frames_ = 0;
    uint64_t lost_frames_ = 0;
    int map_time_ = 0;        ///< frame counter of the map (frames fused or tracked)
    int map_start_time_ = 0;  ///< map_time_ when the static map was (re)built
    uint64_t lost_run_ = 0;   ///< frames lost in a row
    GuardCounters guards_;
    bool started_ = false;
    bool lost_ = false;
    cv::Size input_size_;
};

}  // namespace df::slam
