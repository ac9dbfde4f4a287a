#pragma once
/// `df_slam offline --foxglove`: the run as Foxglove views in one MCAP file (common/foxglove, the
/// channels `df/foxglove/...` that `df_tap record --foxglove` and `df_tap bridge` make), so a run
/// without DDS opens in Foxglove Studio with deploy/foxglove/layout.json: the colour image with
/// the instances' boxes, the masks, the depth, the camera and object frames, the camera path and
/// object boxes, and the map every `map_every` frames. Colour and masks as JPEG (quality 90),
/// chunks compressed with zstd.
#include <array>
#include <memory>
#include <string>

#include "core/status.hpp"
#include "dynamics/frame_segments.hpp"
#include "foxglove/scene.hpp"
#include "io/rgbd_image.hpp"
#include "mcap/mcap_writer.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam_service {

class FoxgloveOutput {
  public:
    /// Creates `path` (kIoError naming it when it cannot). map_every: frames between map clouds
    /// (0: none).
    static Result<FoxgloveOutput> open(const std::string& path, int map_every);

    /// The views of frame `seq`: its image, the instances it came with, its poses, and the map
    /// every map_every frames.
    Status write(uint64_t seq, const io::RgbdImage& image, const dynamics::FrameSegments& segments,
                 const slam::FrameReport& report, const slam::SlamSystem& system);
    Status close();

  private:
    FoxgloveOutput(std::unique_ptr<mcap::Writer> writer, int map_every,
                   const foxglove::SceneOptions& options);
    Status put(const std::vector<foxglove::Message>& messages, uint64_t seq);

    std::unique_ptr<mcap::Writer> writer_;
    int map_every_;
    std::unique_ptr<foxglove::SceneEncoder> encoder_;
    std::array<uint16_t, foxglove::kChannelCount> channels_{};
};

}  // namespace df::slam_service
