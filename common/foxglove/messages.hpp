#pragma once
/// DetectFusion's data as Foxglove messages (schemas in schemas.idl, "omgidl"; every message
/// CDR-encoded, "cdr"), so that Foxglove Studio shows recordings and the live bridge as pictures
/// and a 3-D scene: the camera image with boxes and masks, the camera and object poses as frame
/// transforms, the map as a point cloud, object boxes as scene entities. Frames are named
/// kWorldFrame, kCameraFrame and object_frame(id). Stamps are integer nanoseconds. DDS-free.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::foxglove {

using Bytes = std::vector<uint8_t>;

/// The IDL text every channel carries as its schema (all the types, none included).
const char* idl_text();

/// Schema names as Foxglove Studio's panels know them for "omgidl" schemas.
inline constexpr const char* kRawImage = "foxglove::RawImage";
inline constexpr const char* kCompressedImage = "foxglove::CompressedImage";
inline constexpr const char* kImageAnnotations = "foxglove::ImageAnnotations";
inline constexpr const char* kFrameTransform = "foxglove::FrameTransform";
inline constexpr const char* kPointCloud = "foxglove::PointCloud";
inline constexpr const char* kSceneUpdate = "foxglove::SceneUpdate";

inline constexpr const char* kWorldFrame = "world";
inline constexpr const char* kCameraFrame = "camera";
/// "object_<id>".
std::string object_frame(uint32_t id);

/// An RGB colour 0..255 and an alpha 0..1.
struct Rgba {
    double r = 255, g = 255, b = 255, a = 1;
};

/// An uncompressed image: CV_8UC3 as "rgb8" (R,G,B bytes), CV_8UC1 as "mono8", CV_16UC1 as
/// "16UC1" (little endian). kInvalidArgument for another type or an empty image.
Result<Bytes> raw_image(int64_t stamp_ns, const std::string& frame_id, const cv::Mat& image);

/// A compressed image (format "jpeg" or "png") from its encoded bytes.
Bytes compressed_image(int64_t stamp_ns, const std::string& frame_id, const uint8_t* data,
                       size_t size, const std::string& format);

/// A labelled box on an image, in its pixels.
struct ImageBox {
    cv::Rect2f box;
    std::string label;  ///< "car 0.91"; "" draws no text
    Rgba colour;
};

/// Boxes as closed outlines (LINE_LOOP) with their labels above them, on white text over the
/// box's colour.
Bytes image_annotations(int64_t stamp_ns, const std::vector<ImageBox>& boxes);

/// The pose of `child` in `parent` (parent_T_child).
Bytes frame_transform(int64_t stamp_ns, const std::string& parent, const std::string& child,
                      const Eigen::Isometry3d& parent_T_child);

/// A point of the map cloud: position in the cloud's frame (metres) and colour.
struct CloudPoint {
    float x = 0, y = 0, z = 0;
    uint8_t r = 0, g = 0, b = 0, a = 255;
};

/// Points as fields x, y, z (float32) and red, green, blue, alpha (uint8), 16 bytes a point.
Bytes point_cloud(int64_t stamp_ns, const std::string& frame_id,
                  const std::vector<CloudPoint>& points);

/// An axis-aligned box in its own frame (e.g. an object's model bounds in object_frame(id)),
/// drawn as a translucent cube with a label above it, locked to that frame.
struct SceneBox {
    std::string id;        ///< entity id, unique per box ("object_3")
    std::string frame_id;  ///< the frame the box is given in
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< metres
    std::string label;
    Rgba colour;
};

/// A polyline in a frame (e.g. the camera path in the world frame).
struct ScenePath {
    std::string id;
    std::string frame_id;
    std::vector<Eigen::Vector3d> points;
    Rgba colour;
};

/// A scene update: deletes every entity shown before, then adds `boxes` and `paths`.
Bytes scene_update(int64_t stamp_ns, const std::vector<SceneBox>& boxes,
                   const std::vector<ScenePath>& paths);

}  // namespace df::foxglove
