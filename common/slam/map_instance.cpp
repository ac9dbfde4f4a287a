#include "slam/map_instance.hpp"

namespace df::slam {

Result<TrackingResult> MapInstance::track(const Frame& frame,
                                          const Eigen::Isometry3d& initial_map_T_camera,
                                          const cv::Mat& mask, const TrackingConfig& config) const {
    return slam::track(frame, model_, map_T_model_, initial_map_T_camera, mask, config);
}

Result<cv::Mat> MapInstance::residuals(const Frame& frame, const Eigen::Isometry3d& map_T_camera,
                                       const TrackingConfig& config,
                                       cv::Mat* photometric) const {
    return slam::residual_image(frame, model_, map_T_model_, map_T_camera, config, photometric);
}

Status MapInstance::predict(const Frame& frame, const Eigen::Isometry3d& map_T_camera,
                            int map_time, const map::PredictionConfig& config,
                            map::ModelPrediction* out) const {
    const FrameLevel& level = frame.levels[0];
    return map_.predict_into(map_T_camera.cast<float>(), level.intrinsics, level.width(),
                             level.height(), map_time, config, *out);
}

Status MapInstance::predict_model(const Frame& frame, const Eigen::Isometry3d& map_T_camera,
                                  int map_time, const map::PredictionConfig& config) {
    map::ModelPrediction prediction;
    DF_RETURN_IF_ERROR(predict(frame, map_T_camera, map_time, config, &prediction));
    model_.vertex = prediction.vertex;
    model_.normal = prediction.normal;
    model_.colour = prediction.colour;
    map_T_model_ = map_T_camera;
    model_stale_ = false;
    return Status::ok();
}

Result<map::FusionStats> MapInstance::fuse(const Frame& frame, const cv::Mat& rgb,
                                           const cv::Mat& mask,
                                           const Eigen::Isometry3d& map_T_camera, int map_time,
                                           bool associate_by_prediction,
                                           const map::PredictionConfig& prediction,
                                           bool create_surfels, bool keep_model_layer) {
    layers_fresh_ = false;
    const FrameLevel& level = frame.levels[0];
    cv::Mat association;
    const bool two_layers = associate_by_prediction && keep_model_layer && map_.size() > 0;
    if (two_layers) {
        map::PredictionConfig every_active = prediction;
        every_active.min_confidence = 0.f;
        DF_RETURN_IF_ERROR(map_.predict_two_layers(map_T_camera.cast<float>(), level.intrinsics,
                                                   level.width(), level.height(), map_time,
                                                   every_active, prediction.min_confidence,
                                                   layers_));
        association = layers_.index;
    } else if (associate_by_prediction && map_.size() > 0) {
        map::PredictionConfig every_active = prediction;
        every_active.min_confidence = 0.f;
        DF_RETURN_IF_ERROR(predict(frame, map_T_camera, map_time, every_active, &association_));
        association = association_.index;
    }
    map::FuseOptions options{create_surfels, frame.sensor_size};
    if (two_layers) options.index_after = &index_after_;
    Result<map::FusionStats> stats =
        map_.fuse(level.vertex, level.normal, rgb, mask, association, map_T_camera.cast<float>(),
                  level.intrinsics, map_time, options);
    if (stats && two_layers) {
        layers_fresh_ = true;
        layers_pose_ = map_T_camera;
        layers_min_confidence_ = prediction.min_confidence;
    }
    return stats;
}

Result<bool> MapInstance::model_from_association(const Frame& frame,
                                                 const Eigen::Isometry3d& map_T_camera,
                                                 const map::PredictionConfig& config) {
    if (!layers_fresh_ || layers_pose_.matrix() != map_T_camera.matrix() ||
        layers_min_confidence_ != config.min_confidence) {
        return false;
    }
    layers_fresh_ = false;
    // Into the buffers the model does not use: its images are never overwritten under it.
    map::ModelPrediction& out = model_buffers_[next_buffer_];
    next_buffer_ = 1 - next_buffer_;
    DF_RETURN_IF_ERROR(map_.refresh_prediction(index_after_, layers_, map_T_camera.cast<float>(),
                                               frame.levels[0].intrinsics, config.min_confidence,
                                               config, out));
    model_.vertex = out.vertex;
    model_.normal = out.normal;
    model_.colour = out.colour;
    map_T_model_ = map_T_camera;
    model_stale_ = false;
    return true;
}

Result<map::FusionStats> MapInstance::carve(const Frame& frame, const cv::Mat& mask,
                                            const Eigen::Isometry3d& map_T_camera, int map_time,
                                            bool keep_stable) {
    const FrameLevel& level = frame.levels[0];
    return map_.carve(level.vertex, mask, map_T_camera.cast<float>(), level.intrinsics, map_time,
                      keep_stable, frame.sensor_size);
}

}  // namespace df::slam
