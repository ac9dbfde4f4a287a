#pragma once
/// The command-line mode of the segmentation services: one frame read from a colour and a depth
/// file instead of the frames topic (`df_geoseg --depth D`, `df_fusion --color C --depth D`), and
/// the pictures they write. No DDS is started in this mode.
#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"

namespace df::service {

struct FrameFileFlags {
    std::string color;                ///< colour picture (8-bit); "" when not given
    std::string depth;                ///< depth picture (16-bit, raw units); "" = not in this mode
    std::string preset = "fr3";       ///< camera intrinsics preset (io::intrinsics_preset)
    double depth_units_per_m = 5000;  ///< TUM: 5000; OpenNI, 7-Scenes: 1000
    std::string out_dir = ".";        ///< where pictures go ("" writes none)

    bool given() const { return !depth.empty() || !color.empty(); }
};

/// Adds --color, --depth, --preset, --depth-scale and --out to `app`.
void add_frame_file_flags(CLI::App& app, FrameFileFlags* flags);

/// The frame the flags name; errors name the file or the flag.
Result<io::RgbdImage> read_frame_files(const FrameFileFlags& flags);

/// Writes an R,G,B picture to out_dir/<stem of the depth file>_<suffix>.png (out_dir made if
/// missing) and returns its path; "" when out_dir is "". kIoError naming the file on failure.
Result<std::string> write_picture(const FrameFileFlags& flags, const std::string& suffix,
                                  const cv::Mat& rgb);

/// The same for an image written as it is (B,G,R, or a 16-bit label image).
Result<std::string> write_image(const FrameFileFlags& flags, const std::string& suffix,
                                const cv::Mat& image);

}  // namespace df::service
