#pragma once
/// An RGB-D frame as the libraries see it (no DDS): plain OpenCV matrices.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace df::io {

/// Pinhole intrinsics of the depth-registered colour image, in pixels.
struct Intrinsics {
    double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;  // TUM fr3
};

/// Maximum image size any topic carries (fixed-size shared-memory samples).
constexpr int kMaxWidth = 640;
constexpr int kMaxHeight = 480;

struct RgbdImage {
    cv::Mat rgb;                        ///< CV_8UC3, R,G,B byte order, registered to depth
    cv::Mat depth;                      ///< CV_16UC1 in raw units; 0 = invalid
    double depth_units_per_m = 5000.0;  ///< TUM: 5000, OpenNI (mm): 1000
    Intrinsics intrinsics;
    int64_t sensor_ns = 0;  ///< the source's own time stamp (dataset stamp, device clock), ns
    uint64_t index = 0;     ///< position in the source (0-based)
    std::string rgb_path, depth_path;  ///< where it came from, for messages ("" for live)
};

/// What a source answers when asked for the next frame.
struct FrameRead {
    enum class Kind { kFrame, kBadFrame, kEnd };
    Kind kind = Kind::kEnd;
    RgbdImage image;    ///< valid when kind == kFrame
    std::string error;  ///< for kBadFrame: what and where (file, line), one line
};

/// A stream of RGB-D frames: a TUM folder, a live camera, ...
class FrameSource {
  public:
    virtual ~FrameSource() = default;
    /// Blocks until the next frame (live) or reads it (recorded). A bad frame is reported as
    /// kBadFrame with a message and the source moves on; kEnd after the last frame.
    virtual FrameRead next() = 0;
    /// Frames the source has in all (recorded), or -1 when unknown (live).
    virtual int64_t size() const { return -1; }
    /// One-line description for the start-up log.
    virtual std::string describe() const = 0;
};

}  // namespace df::io
