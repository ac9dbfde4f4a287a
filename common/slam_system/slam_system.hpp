#pragma once
/// The static-scene dense SLAM loop: preprocess -> track against the model predicted at the
/// previous pose -> fuse into the surfel map -> predict the model at the new pose. DDS-free:
/// the offline command and the SLAM service both drive it one image at a time.
///
/// Designed for the dynamic system to come: every call takes a per-pixel mask of pixels to leave
/// out of tracking and fusion, and the static map is one map among the object maps to follow.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "io/tum/trajectory.hpp"
#include "map/surfel_map.hpp"
#include "slam/frame.hpp"
#include "slam/tracker.hpp"
#include "slam_system/system_config.hpp"

namespace df::slam {

/// Milliseconds spent in each stage of one frame (wall clock).
struct StageTimes {
    double preprocess_ms = 0, tracking_ms = 0, fusion_ms = 0, prediction_ms = 0, total_ms = 0;
    /// ("preprocess", ms), ... in pipeline order, for timing log lines.
    std::vector<std::pair<std::string, double>> steps() const;
};

/// What one call of process() did.
struct FrameReport {
    uint64_t frame_number = 0;  ///< 0-based count of frames given to process()
    int64_t sensor_ns = 0;      ///< the image's stamp
    bool first = false;         ///< the frame that started the map (pose = initial pose)
    TrackingResult tracking;    ///< state kOk also for the first frame (figures 0)
    Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();  ///< as reported
    bool fused = false;
    map::FusionStats fusion;
    StageTimes times;
};

class SlamSystem {
  public:
    /// Fails (kInvalidArgument naming the field) when the configuration is not usable.
    static Result<SlamSystem> create(const SystemConfig& config,
                                     const Eigen::Isometry3d& initial_world_T_camera =
                                         Eigen::Isometry3d::Identity());

    /// Processes the next image. `mask`: empty, or CV_8UC1 of the image's size, non-zero =
    /// leave the pixel out of tracking and fusion. kInvalidArgument for an unusable image (wrong
    /// type, size changed since the first frame, bad intrinsics); the system is unchanged then
    /// and the next good image goes on from the last pose.
    Result<FrameReport> process(const io::RgbdImage& image, const cv::Mat& mask = cv::Mat());

    /// Poses of the frames tracked (state kOk, and the first), in order: the trajectory in TUM
    /// form (stamps from sensor_ns). Lost frames are left out (`lost_frames()` counts them).
    const std::vector<io::StampedPose>& trajectory() const { return trajectory_; }
    uint64_t frames() const { return frames_; }
    uint64_t lost_frames() const { return lost_frames_; }
    /// True when the last frame was lost.
    bool lost() const { return lost_; }
    const map::SurfelMap& static_map() const { return map_; }
    const SystemConfig& config() const { return config_; }
    /// The current pose (the last tracked one).
    const Eigen::Isometry3d& world_T_camera() const { return world_T_camera_; }
    /// The model the next frame is tracked against, and the pose it was predicted at.
    const ModelView& model() const { return model_; }
    const Eigen::Isometry3d& world_T_model() const { return world_T_model_; }

    /// Writes trajectory() as a TUM file.
    Status write_trajectory(const std::string& file) const;
    /// Writes the static map's stable surfels (all when stable_only is false) as binary PLY.
    Status write_map(const std::string& file, bool stable_only = true) const;

  private:
    explicit SlamSystem(const SystemConfig& config, const Eigen::Isometry3d& initial);
    /// The image reduced to the processing resolution (mask alike).
    void downscale(const io::RgbdImage& in, const cv::Mat& mask_in, io::RgbdImage* out,
                   cv::Mat* mask_out) const;
    /// Fuses the frame at world_T_camera_; association: empty or the index image of a
    /// prediction at that pose.
    Status fuse(const Frame& frame, const io::RgbdImage& image, const cv::Mat& mask,
                const cv::Mat& association, FrameReport* report);
    /// Predicts the map at world_T_camera_ (surfels with confidence >= min_confidence).
    Status predict(const Frame& frame, float min_confidence, map::ModelPrediction* out,
                   FrameReport* report);

    SystemConfig config_;
    map::SurfelMap map_;
    Eigen::Isometry3d world_T_camera_;
    Eigen::Isometry3d last_motion_ = Eigen::Isometry3d::Identity();  ///< previous_T_current
    ModelView model_;
    map::ModelPrediction association_;  ///< reused buffers of fusion's association prediction
    Eigen::Isometry3d world_T_model_ = Eigen::Isometry3d::Identity();  ///< pose model_ is at
    std::vector<io::StampedPose> trajectory_;
    uint64_t frames_ = 0;
    uint64_t lost_frames_ = 0;
    int map_time_ = 0;  ///< frame counter of the map (frames fused or tracked)
    bool started_ = false;
    bool lost_ = false;
    cv::Size input_size_;
};

}  // namespace df::slam
