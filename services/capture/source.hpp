#pragma once
/// The frame source a CaptureConfig names (TUM folder or OpenNI2 device), shared by the capture
/// service and the offline SLAM command.
#include <memory>

#include "capture.pb.h"
#include "core/status.hpp"
#include "io/rgbd_image.hpp"

namespace df::capture {

/// Opens the source the configuration names. Errors name the folder, file or device.
Result<std::unique_ptr<io::FrameSource>> open_source(const config::CaptureConfig& config);

}  // namespace df::capture
