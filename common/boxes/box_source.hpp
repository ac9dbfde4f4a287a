#pragma once
/// What produces the boxes of one image, shared by the detector service and `df_slam offline`:
/// YOLO through df_detect, or the SIMULATED detector reading a generated sequence's ground truth
/// (instances/<stamp>.png and instances.json; named as such wherever it is used). DDS-free.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "detect/detection.hpp"
#include "detector.pb.h"
#include "io/rgbd_image.hpp"

namespace df::boxes {

class BoxSource {
  public:
    virtual ~BoxSource() = default;
    /// Boxes of `image` (R,G,B; sensor_ns names the ground-truth file of the simulated source),
    /// in its pixels. `seq` seeds the simulated source's errors.
    virtual Result<std::vector<detect::Detection>> detect(const io::RgbdImage& image,
                                                          uint64_t seq) = 0;
    virtual std::string describe() const = 0;
};

/// The source a configuration names; errors name the model file or sequence folder.
Result<std::unique_ptr<BoxSource>> open_source(const config::DetectorServiceConfig& config);

}  // namespace df::boxes
