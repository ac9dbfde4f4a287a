#pragma once
/// The size of a PNG or JPEG image read from its header (PNG IHDR, JPEG SOFn), so that an image
/// too large or of the wrong size is refused before any pixel is decoded: cv::imread of a
/// 16000x16000 PNG allocates 768 MB whatever its file size.
#include <string>

#include "core/status.hpp"

namespace df::io {

struct ImageHeader {
    enum class Format { kPng, kJpeg };
    Format format = Format::kPng;
    int width = 0, height = 0;  ///< pixels, > 0
};

/// Reads only the header of `path` (at most a few kB for PNG; JPEG segments are skipped by their
/// lengths). kNotFound if there is no such file; kInvalidArgument if it is neither a PNG nor a
/// JPEG, or its header is truncated or has a zero or absurd (> 2^31 - 1) size.
Result<ImageHeader> read_image_header(const std::string& path);

/// Checks the header's size before decoding: no larger than max_width x max_height, and equal
/// to width x height when those are > 0. The message says expected vs found.
Status check_image_size(const ImageHeader& header, int max_width, int max_height, int width,
                        int height);

}  // namespace df::io
