#pragma once
/// A small PNG encoder for the generator's three image kinds (8-bit RGB, 16-bit grey): one fixed
/// row filter and zlib level 1, about twice as fast as cv::imencode (whose libpng tries every
/// filter on every row). Output bytes depend only on the pixels and the settings.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "core/status.hpp"

namespace df::sim {

enum class PngFilter : uint8_t { kNone = 0, kSub = 1, kUp = 2, kAverage = 3, kPaeth = 4 };

struct PngSettings {
    PngFilter filter = PngFilter::kSub;
    int level = 1;     ///< zlib level 0..9
    int strategy = 0;  ///< zlib strategy: 0 default, 1 filtered, 2 Huffman only, 3 RLE
};

/// Encodes CV_8UC1, CV_8UC3 (bytes taken as R,G,B, i.e. PNG order) or CV_16UC1 (host order;
/// written big-endian as PNG wants). kInvalidArgument for other types, kInternal on zlib errors.
Result<std::vector<uint8_t>> encode_png(const cv::Mat& image, const PngSettings& settings);

}  // namespace df::sim
