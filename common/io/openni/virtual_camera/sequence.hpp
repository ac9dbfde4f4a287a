#pragma once
/// The recorded RGB-D sequence a virtual camera plays: a folder with associations.txt
/// (lines "t_rgb rgb_path t_depth depth_path", '#' comments), 8-bit colour PNGs and 16-bit depth
/// PNGs. Self-contained on purpose: the driver is loaded by OpenNI2 into any process and must not
/// drag the project's libraries along.
#include <cstdint>
#include <string>
#include <vector>

namespace df::virtual_camera {

/// Driver settings, read from the environment when a device is opened.
struct Settings {
    double depth_units_per_m =
        5000.0;             ///< DF_VIRTUAL_CAMERA_DEPTH_SCALE: raw depth units per metre
    double fx = 535.4;      ///< DF_VIRTUAL_CAMERA_FX, pixels (gives the horizontal FOV)
    double fy = 539.2;      ///< DF_VIRTUAL_CAMERA_FY, pixels (gives the vertical FOV)
    bool lockstep = false;  ///< DF_VIRTUAL_CAMERA_LOCKSTEP=1: one frame per reader wait
    bool loop = false;      ///< DF_VIRTUAL_CAMERA_LOOP=1: start over after the last frame

    /// Reads the DF_VIRTUAL_CAMERA_* variables; false with a message on a malformed value.
    static bool from_env(Settings* out, std::string* error);
};

struct SequenceEntry {
    double rgb_stamp_s = 0.0, depth_stamp_s = 0.0;
    std::string rgb_path, depth_path;  ///< absolute (folder + relative path of the file)
    int line = 0;                      ///< line in associations.txt, for messages
};

struct Sequence {
    std::string folder;
    std::vector<SequenceEntry> entries;
    int width = 0, height = 0;     ///< size of the first frame; every frame must have it
    double period_s = 1.0 / 30.0;  ///< median spacing of the depth stamps

    /// Parses <folder>/associations.txt and reads the first frame's size. False with a message
    /// naming the file (and line) otherwise.
    static bool load(const std::string& folder, Sequence* out, std::string* error);
};

/// One decoded frame pair, ready to be copied into OpenNI frames.
struct FramePair {
    std::vector<uint8_t> rgb;        ///< width x height x 3, R,G,B
    std::vector<uint16_t> depth_mm;  ///< width x height, millimetres, 0 = invalid
    uint64_t rgb_stamp_us = 0, depth_stamp_us = 0;
};

/// Decodes entry `index` and converts depth to millimetres (round(raw * 1000 / units_per_m)).
bool read_frame(const Sequence& sequence, size_t index, double depth_units_per_m, FramePair* out,
                std::string* error);

}  // namespace df::virtual_camera
