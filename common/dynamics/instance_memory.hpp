#pragma once
/// Rigid instances remembered over the frames where the detector misses them. Until object maps
/// track rigid objects, their pixels are left out of the static map; a detector that finds a
/// static chair in one frame and not in the next would leave a hole in the map that the next
/// frame sees the chair through, and motion segmentation would take the chair for a mover
/// (measured: 6 % of the pixels of a static scene flagged with YOLOv5s, 0 % with the rigid
/// instances kept in; docs/dynamics.md, "Remembered rigid instances"). The memory keeps each
/// rigid instance pixel, with its depth, in the camera of the frame that saw it; the next frame
/// looks it up through the camera's motion and keeps a pixel only where its own depth agrees
/// with the remembered one (so an object that moved away frees the floor it stood on), for at
/// most `frames` frames after the detector last saw it. DDS-free.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "params/slam_params.hpp"

namespace df::dynamics {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Memory), and generated into params/slam_params.hpp.
using InstanceMemoryConfig = params::slam::Memory;

std::string validate(const InstanceMemoryConfig& config);

class InstanceMemory {
  public:
    /// The pixels of the current frame (CV_8UC1, 255) that the memory holds: those whose point
    /// (`vertex`: CV_32FC3, current camera, metres; z <= 0 invalid), moved into the last stored
    /// frame's camera by previous_T_current, projects (fx, fy, cx, cy: both frames) onto a
    /// remembered pixel of about the same depth. Zeros when the memory is empty or off.
    cv::Mat recall(const cv::Mat& vertex, const Eigen::Isometry3f& previous_T_current, float fx,
                   float fy, float cx, float cy, const InstanceMemoryConfig& config);
    /// Stores the current frame: `detected` (CV_8UC1, this frame's rigid instance pixels) as
    /// just seen, the pixels of the last recall() that are not detected one frame older;
    /// `depth_m` (CV_32F, metres, 0 invalid) is the frame's depth.
    void store(const cv::Mat& detected, const cv::Mat& depth_m, const InstanceMemoryConfig& config);
    /// Forgets everything (tracking lost: the camera's motion is unknown).
    void clear();
    /// Pixels held.
    int size() const;

  private:
    cv::Mat depth_;     ///< CV_32F, depth of each remembered pixel in its frame's camera; 0 none
    cv::Mat age_;       ///< CV_16U, frames since the detector saw it
    cv::Mat recalled_;  ///< CV_16U, age + 1 of the pixels the last recall() kept; 0 none
};

}  // namespace df::dynamics
