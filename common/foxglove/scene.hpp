#pragma once
/// What Foxglove Studio shows of a running or recorded pipeline, made from the library types the
/// services exchange: the colour and depth images, the detector's boxes over the image, the object
/// masks tinted over it, the camera and object poses as frame transforms, the camera's path and
/// the objects' boxes as a 3-D scene, and the map as a point cloud. One SceneEncoder per stream;
/// each call returns the Foxglove messages (zero or more) that one input makes, on the channels
/// below. Used by `df_tap record --foxglove` and `df_tap bridge`. DDS-free.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "detect/detection.hpp"
#include "dynamics/frame_segments.hpp"
#include "foxglove/messages.hpp"
#include "io/rgbd_image.hpp"

namespace df::foxglove {

enum class Channel { kColor, kDepth, kDetections, kMasks, kTransforms, kScene, kMap };
inline constexpr int kChannelCount = 7;

/// Bounds on what the views cost (bandwidth of the bridge, size of a recording).
struct SceneOptions {
    /// Images (colour, depth, masks) and boxes scaled by this, (0, 1].
    double image_scale = 1.0;
    /// 0: colour and masks as raw rgb8 images (exact pixels); 1..100: JPEG of this quality.
    int jpeg_quality = 0;
    bool depth = true;  ///< the depth image channel
    /// Longest camera path drawn, in poses (older ones dropped).
    size_t max_path_poses = 10000;
};

struct ChannelSpec {
    std::string topic;   ///< "<prefix>/color", ...
    std::string schema;  ///< kRawImage, ...
};

/// The channel's topic under `prefix` (e.g. "df/foxglove") and its schema name under `options`.
ChannelSpec channel_spec(Channel channel, const std::string& prefix, const SceneOptions& options);

struct Message {
    Channel channel;
    int64_t stamp_ns = 0;
    Bytes data;
};

/// An object's pose in one frame, as SLAM reports it.
struct ObjectState {
    uint32_t id = 0;
    int class_id = -1;
    Eigen::Isometry3d world_T_object = Eigen::Isometry3d::Identity();
    bool tracked = false;
};

/// An object model's extent in its own frame (metres).
struct ObjectBounds {
    uint32_t id = 0;
    int class_id = -1;
    Eigen::Vector3f min = Eigen::Vector3f::Zero(), max = Eigen::Vector3f::Zero();
};

class SceneEncoder {
  public:
    explicit SceneEncoder(SceneOptions options = {}) : options_(options) {}

    /// Only channels set here are made (the bridge skips what no client subscribed to). All by
    /// default.
    void set_wanted(Channel channel, bool wanted) { wanted_[static_cast<int>(channel)] = wanted; }
    bool wanted(Channel channel) const { return wanted_[static_cast<int>(channel)]; }

    /// Colour and depth of frame `seq`. The colour is copied and kept a few frames for the masks
    /// (`image` may be a view of memory the caller reuses after the call).
    std::vector<Message> frame(uint64_t seq, int64_t stamp_ns, const io::RgbdImage& image);
    /// The detector's boxes of frame `seq`, in the pixels of an image `width` wide.
    std::vector<Message> detections(int64_t stamp_ns, const std::vector<detect::Detection>& boxes,
                                    int width);
    /// The object instances of frame `seq` tinted over its colour image (black if not kept).
    std::vector<Message> instances(uint64_t seq, int64_t stamp_ns,
                                   const dynamics::LabelImage& labels);
    /// world_T_camera of a frame: a transform, and the camera path with the object boxes.
    std::vector<Message> camera_pose(int64_t stamp_ns, const Eigen::Isometry3d& world_T_camera);
    /// Every object's pose in a frame: a transform per object.
    std::vector<Message> object_poses(int64_t stamp_ns, const std::vector<ObjectState>& objects);
    /// The map (world frame) and the object models' bounds.
    std::vector<Message> map(int64_t stamp_ns, const std::vector<CloudPoint>& points,
                             const std::vector<ObjectBounds>& bounds);

  private:
    /// rgb scaled by image_scale, as raw rgb8 or JPEG.
    void image(Channel channel, int64_t stamp_ns, const cv::Mat& rgb,
               std::vector<Message>* out) const;
    Message scene(int64_t stamp_ns) const;

    SceneOptions options_;
    std::array<bool, kChannelCount> wanted_ = {true, true, true, true, true, true, true};
    std::deque<std::pair<uint64_t, cv::Mat>> colours_;  ///< the last few frames' colour, by seq
    std::deque<Eigen::Vector3d> path_;                  ///< camera positions, world frame
    std::map<uint32_t, ObjectBounds> bounds_;           ///< by object id
    std::map<uint32_t, bool> tracked_;                  ///< objects of the last object_poses
};

}  // namespace df::foxglove
