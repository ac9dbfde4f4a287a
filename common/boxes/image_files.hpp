#pragma once
/// Detection on picture files, without DDS (`df_detector --image FILE...`, like darknet's
/// `detect`): read the picture, run a BoxSource on it, print the boxes and write a copy with the
/// boxes drawn. DDS-free.
#include <string>
#include <vector>

#include "boxes/box_source.hpp"
#include "core/status.hpp"
#include "detect/detection.hpp"

namespace df::boxes {

/// What one picture gave.
struct ImageDetections {
    std::string file;  ///< the picture read
    int width = 0;     ///< its size in pixels
    int height = 0;
    std::vector<detect::Detection> detections;  ///< in its pixels, best score first
    double detect_ms = 0;                       ///< time spent in the detector
    std::string written;  ///< the picture with the boxes drawn ("" when none was asked for)
};

/// Reads `file` (any format OpenCV reads), detects with `source` and, when out_dir is not empty,
/// writes the picture with the boxes drawn to out_dir/<file stem>_detections.jpg (out_dir is
/// made if missing). Errors name the file: kNotFound when it does not exist, kIoError when it is
/// not a picture OpenCV can read (corrupt, truncated, another format) or the output cannot be
/// written; a detector error is returned with the file prepended.
Result<ImageDetections> detect_image_file(BoxSource& source, const std::string& file,
                                          const std::string& out_dir);

/// The lines `df_detector --image` prints for one picture: a header with file, size, count and
/// time, then one line per detection ("  dog         0.91  x 133 y 220 w 179 h 322").
std::string describe(const ImageDetections& result);

}  // namespace df::boxes
