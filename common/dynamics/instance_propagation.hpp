#pragma once
/// Instances carried forward over frames without fresh detections (issue 13). A detector slower
/// than the camera answers for some frames only; the others would have no person or object
/// masks, or (the fusion service's reuse) an older frame's boxes, which a walking person has
/// left. Here the last frame's instances are moved into the current frame instead: every pixel
/// of an instance, with its depth, through the camera's motion (current_T_previous), then snapped
/// to the current frame's geometric segments: a segment joins the instance that covers at least
/// `min_segment_overlap` of it (a person whose limbs moved), and any other pixel is the
/// instance's where its depth agrees with the warped one (an object merged with the floor in
/// one segment). An instance keeps its id, class, kind and score; its age (frames
/// since the detector saw it) grows by one, and past `max_age_frames` it is dropped. Only what
/// was there before is carried: a new object is left to the next detection. DDS-free.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "dynamics/frame_segments.hpp"
#include "params/slam_params.hpp"

namespace df::dynamics {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Propagation), and generated into params/slam_params.hpp.
using PropagationConfig = params::slam::Propagation;

std::string validate(const PropagationConfig& config);

/// The camera of the label images (pixels of the image they are stored at).
struct PinholeCamera {
    float fx = 0, fy = 0, cx = 0, cy = 0;
};

class InstancePropagation {
  public:
    /// The stored instances moved into the current frame: `depth_m` (CV_32F, metres, 0
    /// invalid) and `geometric` (CV_32SC1, 1..geometric_count, 0 none; may be empty, then only
    /// the warped pixels whose depth agrees count) are the current frame's, of the stored
    /// size. Every row's age is one more than stored; rows past max_age_frames, and rows that
    /// land on no pixel, are left out. Empty (no labels) when nothing is stored.
    LabelImage carry(const cv::Mat& depth_m, const cv::Mat& geometric, int geometric_count,
                     const Eigen::Isometry3f& current_T_previous, const PinholeCamera& camera,
                     const PropagationConfig& config) const;
    /// Stores the frame's final instances and its depth (the next carry() starts from them).
    /// `last_T_stored`: from the stored frame's camera to the last tracked frame's, when the
    /// instances are an earlier frame's (object segments that arrived after their frame was
    /// tracked); carry()'s current_T_previous is then the motion since the last tracked frame.
    void store(const LabelImage& instances, const cv::Mat& depth_m,
               const Eigen::Isometry3f& last_T_stored = Eigen::Isometry3f::Identity());
    /// The smallest age of the stored rows (frames since the detector saw them); -1 if none.
    int freshest_age() const;
    /// Forgets everything (tracking lost: the camera's motion is unknown).
    void clear();
    bool empty() const { return stored_.empty(); }

  private:
    LabelImage stored_;
    cv::Mat depth_;  ///< CV_32F, the stored frame's depth
    Eigen::Isometry3f last_T_stored_ = Eigen::Isometry3f::Identity();
};

}  // namespace df::dynamics
