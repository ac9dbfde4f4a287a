#pragma once
/// A live OpenNI2 camera (Kinect, Xtion, Orbbec, ... or the DfVirtualCamera driver) as a
/// FrameSource: colour RGB888 and depth in millimetres, depth registered to colour.
///
/// OpenNI2 loads its drivers from <directory of libOpenNI2.so.0>/OpenNI2/Drivers. The build makes
/// <build>/openni2/ with a link to the system library, links to the system drivers and our
/// virtual camera driver; run with LD_LIBRARY_PATH=<build>/openni2 to see both real and virtual
/// devices (URI df-virtual://<absolute folder>).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"

namespace df::io {

struct OpenNiConfig {
    std::string uri;                          ///< device URI; "" = the first device OpenNI finds
    int width = 640, height = 480, fps = 30;  ///< mode asked of both streams
    bool register_depth_to_color = true;      ///< hardware registration when the device has it
    bool mirror = false;
    int timeout_ms = 2000;  ///< next() gives up after this long without a frame pair
};

/// One device as OpenNI lists it.
struct OpenNiDeviceInfo {
    std::string uri, name, vendor;
};

class OpenNiSource final : public FrameSource {
  public:
    /// Initialises OpenNI, opens the device and starts its colour and depth streams.
    /// Errors: kNotFound when the device is not there (the message lists the devices found and
    /// where OpenNI looked for drivers), kInvalidArgument when the mode is not offered (the
    /// message lists the modes), kUnavailable when OpenNI or a stream fails.
    static Result<std::unique_ptr<OpenNiSource>> open(const OpenNiConfig& config);

    /// The devices OpenNI sees now (initialises and shuts down OpenNI around the query).
    static Result<std::vector<OpenNiDeviceInfo>> list_devices();

    ~OpenNiSource() override;
    OpenNiSource(const OpenNiSource&) = delete;
    OpenNiSource& operator=(const OpenNiSource&) = delete;

    /// Waits for the next colour + depth pair (same frameIndex with frame sync, else nearest
    /// stamps). rgb CV_8UC3 R,G,B; depth CV_16UC1 mm (depth_units_per_m = 1000); sensor_ns from
    /// the depth frame's device stamp (us -> ns); index = depth frameIndex - first frameIndex.
    /// kBadFrame after timeout_ms without a pair; kEnd once the device is disconnected and
    /// nothing is left (the virtual camera disconnects at the end of its recording).
    FrameRead next() override;
    std::string describe() const override;

    /// Pinhole intrinsics from the depth stream's field of view: fx = width / (2 tan(hfov / 2)),
    /// fy likewise with vfov and height, cx = width / 2, cy = height / 2. Pixels.
    const Intrinsics& intrinsics() const;

  private:
    struct Impl;
    explicit OpenNiSource(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace df::io
