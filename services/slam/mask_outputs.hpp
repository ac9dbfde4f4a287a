#pragma once
/// The per-frame masks a SLAM run writes, named by the frame's stamp (io::stamp_text), all at the
/// input image's resolution, 16-bit label PNGs that `df_eval seg` reads (docs/dynamics.md):
///   <dir>/invalid/<stamp>.png  what was left out of the static map's tracking: the instance ids
///                              of segments/ where an instance was left out, then one id per
///                              motion region
///   <dir>/motion/<stamp>.png   the motion segments of unknown movers, one id per region
///   <dir>/segments/<stamp>.png the object instances the frame came with (detections fused with
///                              geometric segments, or the given masks)
///   <dir>/object_masks/<stamp>.png  the object map id that claimed each pixel (0 none)
///   <dir>/overlay/<stamp>.png  (overlay on) the colour image with what was left out tinted by
///                              kind (person red, rigid blue, unknown mover yellow), boxes and
///                              class names drawn; object maps' pixels in a colour per object
///                              with "#id class"
#include <string>

#include "core/status.hpp"
#include "dynamics/frame_segments.hpp"
#include "io/rgbd_image.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam_service {

class MaskOutputs {
  public:
    /// Creates the folders under `dir`. kIoError naming the folder when it cannot.
    static Result<MaskOutputs> open(const std::string& dir, bool overlay);

    /// Writes the frame's masks. `segments`: what the frame came with (input resolution);
    /// `factor`: the system's processing_downscale (the report's masks are that much smaller).
    Status write(const io::RgbdImage& image, const dynamics::FrameSegments& segments,
                 const slam::FrameReport& report, int factor) const;

  private:
    MaskOutputs(std::string dir, bool overlay) : dir_(std::move(dir)), overlay_(overlay) {}
    std::string dir_;
    bool overlay_;
};

}  // namespace df::slam_service
