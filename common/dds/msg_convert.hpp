#pragma once
/// Conversions between topic samples and the libraries' OpenCV types.
/// Views alias the sample's memory (valid while the sample is): no copy. Reading conversions
/// take only samples that passed check_sample() (dds::Checked), so that a sample whose header
/// claims more pixels than its buffer holds can never be viewed or copied.
#include <algorithm>
#include <cstdint>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "dds/sample_check.hpp"
#include "dynamics/frame_segments.hpp"
#include "df_msgs.h"
#include "io/rgbd_image.hpp"

namespace df::dds {

/// Wall-clock time now, ns since the Unix epoch (the clock of Header.capture_ns).
uint64_t wall_ns();

/// Fills a frame sample from an image. The image must be CV_8UC3 and CV_16UC1 of one size
/// within MAX_WIDTH x MAX_HEIGHT (checked by the sources); aborts otherwise (broken invariant).
void fill_frame(const io::RgbdImage& image, const df_msg_Header& header, df_msg_RgbdFrame* frame);

/// CV_8UC3 (RGB) and CV_16UC1 views of a checked frame sample (width x height).
cv::Mat rgb_view(const Checked<df_msg_RgbdFrame>& frame);
cv::Mat depth_view(const Checked<df_msg_RgbdFrame>& frame);

/// An owning RgbdImage copied from a checked frame sample.
io::RgbdImage to_image(const Checked<df_msg_RgbdFrame>& frame);

/// The frame sample checked and copied; the check's error names the field, value and limit.
Result<io::RgbdImage> to_image(const df_msg_RgbdFrame& frame);

/// A CV_32SC1 label image copied from a checked segments sample (0 = no segment).
cv::Mat labels_of(const Checked<df_msg_GeometricSegments>& segments);

/// The label image and table of a checked object segments sample (labels copied).
dynamics::LabelImage to_label_image(const Checked<df_msg_ObjectSegments>& segments);

/// Frames between frame `seq` and the detections of frame `detections_seq` it was given: 0 for
/// its own (or a newer frame's), at most 65535.
inline int frames_since_detection(uint64_t seq, uint64_t detections_seq) {
    return detections_seq >= seq
               ? 0
               : static_cast<int>(std::min<uint64_t>(seq - detections_seq, 65535));
}

/// Fills an object segments sample: `labels` (CV_16UC1, at most MAX_WIDTH x MAX_HEIGHT) and at
/// most MAX_INSTANCES rows of its table (the rest dropped, counted in the return value).
size_t fill_object_segments(const dynamics::LabelImage& labels, const df_msg_Header& header,
                            df_msg_ObjectSegments* out);

/// A pose (world_T_x) as the topics carry it: translation in metres and a unit quaternion.
inline df_msg_Pose to_pose_msg(const Eigen::Isometry3d& pose) {
    const Eigen::Quaterniond q(pose.linear());
    return df_msg_Pose{pose.translation().x(), pose.translation().y(), pose.translation().z(),
                       q.x(), q.y(), q.z(), q.w()};
}

}  // namespace df::dds
