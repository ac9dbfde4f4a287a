#include "sim/png.hpp"

#include <zlib.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace df::sim {
namespace {

void put_u32(std::vector<uint8_t>* out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<uint8_t>(v >> shift));
}

void put_chunk(std::vector<uint8_t>* out, const char type[4], const uint8_t* data, size_t size) {
    put_u32(out, static_cast<uint32_t>(size));
    const size_t start = out->size();
    out->insert(out->end(), type, type + 4);
    out->insert(out->end(), data, data + size);
    const uLong crc = crc32(0L, out->data() + start, static_cast<uInt>(size + 4));
    put_u32(out, static_cast<uint32_t>(crc));
}

uint8_t paeth(int a, int b, int c) {
    const int p = a + b - c;
    const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return static_cast<uint8_t>(a);
    return static_cast<uint8_t>(pb <= pc ? b : c);
}

/// One filtered scanline (filter byte first) from raw bytes `row` and the previous raw row.
void filter_row(PngFilter f, const uint8_t* row, const uint8_t* prior, size_t n, int bpp,
                uint8_t* out) {
    out[0] = static_cast<uint8_t>(f);
    uint8_t* o = out + 1;
    for (size_t i = 0; i < n; ++i) {
        const int a = i >= static_cast<size_t>(bpp) ? row[i - bpp] : 0;
        const int b = prior ? prior[i] : 0;
        const int c = (prior && i >= static_cast<size_t>(bpp)) ? prior[i - bpp] : 0;
        int predicted = 0;
        switch (f) {
            case PngFilter::kNone:
                predicted = 0;
                break;
            case PngFilter::kSub:
                predicted = a;
                break;
            case PngFilter::kUp:
                predicted = b;
                break;
            case PngFilter::kAverage:
                predicted = (a + b) / 2;
                break;
            case PngFilter::kPaeth:
                predicted = paeth(a, b, c);
                break;
        }
        o[i] = static_cast<uint8_t>(row[i] - predicted);
    }
}

}  // namespace

Result<std::vector<uint8_t>> encode_png(const cv::Mat& image, const PngSettings& settings) {
    int bit_depth = 8, colour_type = 0, bpp = 1;
    switch (image.type()) {
        case CV_8UC1:
            break;
        case CV_8UC3:
            colour_type = 2, bpp = 3;
            break;
        case CV_16UC1:
            bit_depth = 16, bpp = 2;
            break;
        default:
            return error(StatusCode::kInvalidArgument,
                         "PNG encoder: unsupported image type " + std::to_string(image.type()));
    }
    const size_t row_bytes = static_cast<size_t>(image.cols) * bpp;
    // Raw rows in PNG byte order, then filtered, then deflated.
    std::vector<uint8_t> raw(row_bytes * image.rows);
    for (int y = 0; y < image.rows; ++y) {
        uint8_t* dst = raw.data() + row_bytes * y;
        if (bit_depth == 16) {
            const uint16_t* src = image.ptr<uint16_t>(y);
            for (int x = 0; x < image.cols; ++x) {
                dst[2 * x] = static_cast<uint8_t>(src[x] >> 8);
                dst[2 * x + 1] = static_cast<uint8_t>(src[x] & 0xFF);
            }
        } else {
            std::memcpy(dst, image.ptr<uint8_t>(y), row_bytes);
        }
    }
    std::vector<uint8_t> filtered((row_bytes + 1) * image.rows);
    for (int y = 0; y < image.rows; ++y) {
        filter_row(settings.filter, raw.data() + row_bytes * y,
                   y > 0 ? raw.data() + row_bytes * (y - 1) : nullptr, row_bytes, bpp,
                   filtered.data() + (row_bytes + 1) * y);
    }
    z_stream zs;
    std::memset(&zs, 0, sizeof zs);
    if (deflateInit2(&zs, settings.level, Z_DEFLATED, 15, 8, settings.strategy) != Z_OK)
        return error(StatusCode::kInternal, "PNG encoder: deflateInit2 failed");
    std::vector<uint8_t> compressed(deflateBound(&zs, filtered.size()));
    zs.next_in = filtered.data();
    zs.avail_in = static_cast<uInt>(filtered.size());
    zs.next_out = compressed.data();
    zs.avail_out = static_cast<uInt>(compressed.size());
    const int rc = deflate(&zs, Z_FINISH);
    const size_t compressed_size = zs.total_out;
    deflateEnd(&zs);
    if (rc != Z_STREAM_END) return error(StatusCode::kInternal, "PNG encoder: deflate failed");

    std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    out.reserve(compressed_size + 128);
    std::vector<uint8_t> header;
    put_u32(&header, static_cast<uint32_t>(image.cols));
    put_u32(&header, static_cast<uint32_t>(image.rows));
    header.insert(header.end(),
                  {static_cast<uint8_t>(bit_depth), static_cast<uint8_t>(colour_type), 0, 0, 0});
    put_chunk(&out, "IHDR", header.data(), header.size());
    put_chunk(&out, "IDAT", compressed.data(), compressed_size);
    put_chunk(&out, "IEND", nullptr, 0);
    return out;
}

}  // namespace df::sim
