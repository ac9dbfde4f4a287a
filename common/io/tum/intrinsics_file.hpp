#pragma once
/// "<folder>/intrinsics.txt" as df_make_sequence writes it: one line
/// "fx fy cx cy width height depth_units_per_m" ('#' comments), pixels and raw units per metre.
#include <string>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "io/tum/tum_folder.hpp"

namespace df::io {

struct IntrinsicsFile {
    Intrinsics intrinsics;
    int width = 0, height = 0;  ///< the image size the intrinsics are for
    double depth_units_per_m = 0;
};

/// Reads and checks `file`: the size within 1x1..640x480, the intrinsics plausible for it
/// (check_intrinsics), depth_units_per_m finite in (0, 1e6]. kNotFound if there is no such
/// file; kInvalidArgument naming "<file>:<line>", the field, the value and what is allowed.
Result<IntrinsicsFile> read_intrinsics_file(const std::string& file);

/// How to read the TUM folder `folder`: intrinsics, image size and depth scale from
/// "<folder>/intrinsics.txt" when it has one (generated sequences), else the intrinsics preset
/// `preset` (intrinsics_preset; "7scenes" also sets depth 1000 units/m and 65535 invalid).
/// Errors name the file and line (read_intrinsics_file) or the unknown preset.
Result<TumFolderConfig> tum_folder_config(const std::string& folder,
                                          const std::string& preset = "fr3");

}  // namespace df::io
