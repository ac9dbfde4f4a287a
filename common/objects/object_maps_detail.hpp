#pragma once
/// Internal to df_objects: helpers that object_maps.cpp and object_creation.cpp share.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "slam/frame.hpp"

namespace df::objects::detail {

/// Mean of the valid vertices under `mask` (camera frame) of `vertex` (default: the level's);
/// false when there are none.
bool mean_vertex(const slam::FrameLevel& level, const cv::Mat& mask, Eigen::Vector3d* out,
                 const cv::Mat& vertex = cv::Mat());

}  // namespace df::objects::detail
