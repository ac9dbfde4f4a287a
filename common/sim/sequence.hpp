#pragma once
/// A generated sequence: scene, camera path, sensor, size and timing. make_sequence() builds
/// one from a preset; frame_state() gives the poses of frame i; write_sequence() (writer.hpp)
/// renders and writes the folder described in docs/sequence_format.md.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "sim/camera_path.hpp"
#include "sim/render.hpp"
#include "sim/scene.hpp"
#include "sim/sensor.hpp"

namespace df::sim {

/// Version written to sequence.json; bump it when the same preset and seed would give other data.
constexpr const char* kGeneratorVersion = "1.0";

struct Sequence {
    std::string preset, description;
    uint64_t seed = 1;
    int frames = 150;
    double fps = 30.0;
    double first_stamp_s = 1.0;  ///< stamp of frame 0; frame i is at first_stamp_s + i / fps
    int width = 640, height = 480;
    io::Intrinsics intrinsics;  ///< for width x height
    double depth_units_per_m = 5000.0;
    SensorConfig sensor;
    Scene scene;
    CameraPathConfig camera;
    std::vector<std::string> missing_photos;  ///< photos that could not be read (grey decals)
    double static_model_spacing_m = 0.02;     ///< point spacing of models/static.ply
    double object_model_spacing_m = 0.004;    ///< point spacing of models/<object>.ply

    double time_s(int frame) const { return frame / fps; }
    /// Stamp in whole microseconds, so file names, lists and trajectories agree exactly.
    int64_t stamp_us(int frame) const;
};

/// Poses of camera and objects at frame `frame`.
FrameState frame_state(const Sequence& sequence, int frame);
/// Poses of camera and objects at time t_s (seconds from the first frame).
FrameState state_at(const Sequence& sequence, double t_s);

/// Renders frame `frame` without noise (threads <= 0: all).
RenderBuffers render_frame(const Sequence& sequence, int frame, int threads = 0);

/// The sensor's motion blur (SensorConfig::motion_blur; nothing when off): the colour of frame
/// `frame` becomes the mean of blur_samples renders spread over the exposure, centred on the
/// frame's time (`buffers` is that frame's render; depth and instances stay the centre's).
void apply_motion_blur(const Sequence& sequence, int frame, int threads, RenderBuffers* buffers);

/// Intrinsics of a 640x480 calibration scaled to width x height (pixel centres kept aligned).
io::Intrinsics scale_intrinsics(const io::Intrinsics& k640, int width, int height);

struct PresetInfo {
    std::string name;
    std::string summary;
    int default_frames = 300;
};

/// All presets, in the order --list-presets prints them.
const std::vector<PresetInfo>& presets();

struct PresetOptions {
    uint64_t seed = 1;
    int frames = 0;  ///< 0: the preset's default
    int width = 640, height = 480;
    bool noise = true;  ///< false: SensorConfig::ideal()
    std::string photo_folder = "/usr/share/darknet/data";
};

/// Builds a preset. kInvalidArgument (naming the presets) for an unknown name or bad sizes.
Result<Sequence> make_sequence(const std::string& preset, const PresetOptions& options);

}  // namespace df::sim
