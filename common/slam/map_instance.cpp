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
                                           bool create_surfels) {
    cv::Mat association;
    if (associate_by_prediction && map_.size() > 0) {
        map::PredictionConfig every_active = prediction;
        every_active.min_confidence = 0.f;
        DF_RETURN_IF_ERROR(predict(frame, map_T_camera, map_time, every_active, &association_));
        association = association_.index;
    }
    const FrameLevel& level = frame.levels[0];
    return map_.fuse(level.vertex, level.normal, rgb, mask, association, map_T_camera.cast<float>(),
                     level.intrinsics, map_time,
                     map::FuseOptions{create_surfels, frame.sensor_size});
}

Result<map::FusionStats> MapInstance::carve(const Frame& frame, const cv::Mat& mask,
                                            const Eigen::Isometry3d& map_T_camera, int map_time,
                                            bool keep_stable) {
    const FrameLevel& level = frame.levels[0];
    return map_.carve(level.vertex, mask, map_T_camera.cast<float>(), level.intrinsics, map_time,
                      keep_stable, frame.sensor_size);
}

}  // namespace df::slam
