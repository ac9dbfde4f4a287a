#pragma once
/// The invalid mask (DetectFusion, "Tracking"): the pixels of one frame kept out of the static
/// map's tracking refinement and fusion: the object instances of the kinds configured (non-rigid
/// always by default; rigid ones until they get object maps, since a known rigid object may move
/// at any time) and the motion segments of unknown movers. Also as a label image with its table,
/// which is what the SLAM service publishes. DDS-free.
#include <opencv2/core.hpp>
#include <string>

#include "dynamics/frame_segments.hpp"
#include "params/slam_params.hpp"

namespace df::dynamics {

/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Invalid), and generated into params/slam_params.hpp.
using InvalidMaskConfig = params::slam::Invalid;

std::string validate(const InvalidMaskConfig& config);

/// CV_16UC1, the instance ids left out (0 = kept): the instances of `segments.objects` of the
/// configured kinds, then the depth-gated boxes of non-rigid ones with their rows' ids
/// (`depth_m`: CV_32F metres, 0 = invalid, of `size`; may be empty to skip that rule), dilated
/// (where two meet, the larger id wins); zeros of `size` when there are none.
cv::Mat instance_labels(const FrameSegments& segments, const cv::Mat& depth_m, cv::Size size,
                        const InvalidMaskConfig& config);

/// instance_labels() as a CV_8UC1 mask (255 = left out).
cv::Mat instance_mask(const FrameSegments& segments, const cv::Mat& depth_m, cv::Size size,
                      const InvalidMaskConfig& config);

struct InvalidMask {
    cv::Mat tracking;  ///< CV_8UC1, 255 = left out of the static map's tracking (stage 2)
    cv::Mat fusion;    ///< CV_8UC1, 255 = left out of the static map's fusion
    /// `tracking` as labels: the frame's instance ids where instances were left out, then one
    /// id per connected region of motion-segment pixels (kind kUnknown, class -1).
    LabelImage labels;
};

/// Combines `instance_ids` (instance_labels) and `motion` (CV_8UC1 or empty) into the invalid
/// mask; the table lists the instances with pixels in `instance_ids`, then the motion regions.
/// `residual_m`: CV_32F signed residual (positive = the frame's point is farther than the
/// model), NaN where none; may be empty (then fusion == tracking).
InvalidMask combine(const FrameSegments& segments, const cv::Mat& instance_ids,
                    const cv::Mat& motion, const cv::Mat& residual_m,
                    const InvalidMaskConfig& config);

}  // namespace df::dynamics
