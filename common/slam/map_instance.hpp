#pragma once
/// One map of the scene with everything that goes with it from frame to frame: the surfel map,
/// its pose in the world, the model the next frame is tracked against (its prediction) and how
/// the last tracking went. The static map is one instance (id 0, world_T_map the identity); the
/// object maps of the next step are more instances of the same type. DDS-free; SlamSystem
/// orchestrates the instances.
#include <Eigen/Geometry>

#include "core/status.hpp"
#include "map/surfel_map.hpp"
#include "slam/frame.hpp"
#include "slam/tracker.hpp"

namespace df::slam {

class MapInstance {
  public:
    MapInstance(int id, const map::SurfelMapConfig& config) : id_(id), map_(config) {}

    int id() const { return id_; }
    map::SurfelMap& map() { return map_; }
    const map::SurfelMap& map() const { return map_; }
    /// The map's frame in the world (static map: the identity).
    const Eigen::Isometry3d& world_T_map() const { return world_T_map_; }
    void set_world_T_map(const Eigen::Isometry3d& pose) { world_T_map_ = pose; }

    /// The model tracking aligns to, and the camera pose (in the map's frame) it was predicted
    /// at.
    const ModelView& model() const { return model_; }
    const Eigen::Isometry3d& map_T_model() const { return map_T_model_; }
    /// True when the model must be predicted again before it is tracked against (restored from
    /// a checkpoint: the map is there, its rendering not).
    bool model_stale() const { return model_stale_; }
    void mark_model_stale() { model_stale_ = true; }

    /// The last tracking of a frame against this map.
    const TrackingResult& last_tracking() const { return last_tracking_; }
    void set_last_tracking(const TrackingResult& result) { last_tracking_ = result; }

    /// Tracks `frame` against the model; `initial_map_T_camera` is the starting estimate.
    Result<TrackingResult> track(const Frame& frame, const Eigen::Isometry3d& initial_map_T_camera,
                                 const cv::Mat& mask, const TrackingConfig& config) const;
    /// The frame's per-pixel residual against the model with the camera at map_T_camera
    /// (slam::residual_image).
    Result<cv::Mat> residuals(const Frame& frame, const Eigen::Isometry3d& map_T_camera,
                              const TrackingConfig& config,
                              cv::Mat* photometric = nullptr) const;

    /// Renders the map seen from map_T_camera (surfels with confidence >= min_confidence) into
    /// `out`, at the frame's level-0 size and intrinsics.
    Status predict(const Frame& frame, const Eigen::Isometry3d& map_T_camera, int map_time,
                   const map::PredictionConfig& config, map::ModelPrediction* out) const;
    /// Predicts the model the next frame is tracked against from map_T_camera.
    Status predict_model(const Frame& frame, const Eigen::Isometry3d& map_T_camera, int map_time,
                         const map::PredictionConfig& config);
    /// Fuses the frame's level-0 vertices (pixels of `mask` left out) at map_T_camera; with
    /// `associate_by_prediction`, pixels are associated with the surfels a rendering of every
    /// active surfel shows there. `create_surfels` false: only existing surfels are updated.
    /// A crop() of a frame weighs its observations as the whole frame would.
    /// `keep_model_layer` (with associate_by_prediction): the rendering also keeps the surfels
    /// with confidence >= prediction.min_confidence, for model_from_association().
    Result<map::FusionStats> fuse(const Frame& frame, const cv::Mat& rgb, const cv::Mat& mask,
                                  const Eigen::Isometry3d& map_T_camera, int map_time,
                                  bool associate_by_prediction,
                                  const map::PredictionConfig& prediction,
                                  bool create_surfels = true, bool keep_model_layer = false);

    /// After a fuse() with keep_model_layer: makes the model the next frame is tracked against
    /// out of fusion's rendering of the map, brought up to date with the fused map
    /// (map::SurfelMap::refresh_prediction), instead of rendering the map again: the same model
    /// as predict_model() at a fraction of the cost (one rendering per frame instead of two).
    /// `config` as predict_model() would take it; its min_confidence must be the one fuse()
    /// had. false (nothing changed) when the last fuse() made no such rendering (an empty map,
    /// association by centres, no keep_model_layer) or made it at another pose or confidence.
    Result<bool> model_from_association(const Frame& frame, const Eigen::Isometry3d& map_T_camera,
                                        const map::PredictionConfig& config);

    /// The free-space pass alone (map::SurfelMap::carve) with the camera at map_T_camera: the
    /// surfels the frame's level-0 vertices see through are weakened or removed.
    Result<map::FusionStats> carve(const Frame& frame, const cv::Mat& mask,
                                   const Eigen::Isometry3d& map_T_camera, int map_time,
                                   bool keep_stable = false);

  private:
    int id_;
    map::SurfelMap map_;
    Eigen::Isometry3d world_T_map_ = Eigen::Isometry3d::Identity();
    ModelView model_;
    Eigen::Isometry3d map_T_model_ = Eigen::Isometry3d::Identity();
    bool model_stale_ = false;
    TrackingResult last_tracking_;
    map::ModelPrediction association_;  ///< reused buffers of fusion's association rendering
    // fuse() with keep_model_layer: its two-layer rendering, from where, at which confidence,
    // and the surfel indices after that fusion; model_from_association() uses them once.
    map::TwoLayerPrediction layers_;
    bool layers_fresh_ = false;
    Eigen::Isometry3d layers_pose_ = Eigen::Isometry3d::Identity();
    float layers_min_confidence_ = 0.f;
    std::vector<int32_t> index_after_;
    /// model_from_association() alternates between these: the model's images are never the
    /// ones being written.
    map::ModelPrediction model_buffers_[2];
    int next_buffer_ = 0;
};

}  // namespace df::slam
