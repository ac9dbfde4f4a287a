#include "io/tum/image_header.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>

namespace df::io {
namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t big_endian(const unsigned char* p, int bytes) {
    uint32_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
    return v;
}

Status bad(const std::string& what) { return error(StatusCode::kInvalidArgument, what); }

Result<ImageHeader> sized(ImageHeader::Format format, uint32_t width, uint32_t height) {
    const char* name = format == ImageHeader::Format::kPng ? "PNG" : "JPEG";
    if (width == 0 || height == 0 || width > 0x7fffffffu || height > 0x7fffffffu) {
        return bad(std::string(name) + " header gives a size of " + std::to_string(width) + "x" +
                   std::to_string(height) + " pixels");
    }
    ImageHeader header;
    header.format = format;
    header.width = static_cast<int>(width);
    header.height = static_cast<int>(height);
    return header;
}

Result<ImageHeader> png_header(std::ifstream& in) {
    // After the signature: chunk length (13), "IHDR", width, height (big endian).
    unsigned char ihdr[16];
    if (!in.read(reinterpret_cast<char*>(ihdr), sizeof ihdr)) {
        return bad("truncated PNG: no IHDR header");
    }
    if (std::memcmp(ihdr + 4, "IHDR", 4) != 0 || big_endian(ihdr, 4) != 13) {
        return bad("corrupt PNG: its first chunk is not IHDR");
    }
    return sized(ImageHeader::Format::kPng, big_endian(ihdr + 8, 4), big_endian(ihdr + 12, 4));
}

bool is_start_of_frame(int marker) {
    // SOF0..SOF15 but DHT (C4), JPG (C8) and DAC (CC).
    return marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
}

Result<ImageHeader> jpeg_header(std::ifstream& in) {
    constexpr int kMaxSegments = 4096;
    for (int segment = 0; segment < kMaxSegments; ++segment) {
        int c = in.get();
        if (c != 0xff) return bad("corrupt JPEG: expected a marker before the frame header");
        while (c == 0xff) c = in.get();  // fill bytes
        if (c == EOF) break;
        if (c == 0xd9 || c == 0xda) return bad("corrupt JPEG: no frame header before the scan");
        if ((c >= 0xd0 && c <= 0xd7) || c == 0x01) continue;  // markers without a length
        unsigned char length_bytes[2];
        if (!in.read(reinterpret_cast<char*>(length_bytes), 2)) break;
        const uint32_t length = big_endian(length_bytes, 2);
        if (length < 2) return bad("corrupt JPEG: segment length below 2");
        if (is_start_of_frame(c)) {
            unsigned char sof[5];  // precision, height, width
            if (length < 7 || !in.read(reinterpret_cast<char*>(sof), sizeof sof)) break;
            return sized(ImageHeader::Format::kJpeg, big_endian(sof + 3, 2),
                         big_endian(sof + 1, 2));
        }
        in.seekg(length - 2, std::ios::cur);
        if (!in) break;
    }
    return bad("truncated JPEG: no frame header");
}

}  // namespace

Result<ImageHeader> read_image_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return error(StatusCode::kNotFound, "cannot open the file");
    unsigned char start[8] = {};
    in.read(reinterpret_cast<char*>(start), 2);
    if (in.gcount() == 2 && start[0] == 0xff && start[1] == 0xd8) return jpeg_header(in);
    in.read(reinterpret_cast<char*>(start + 2), 6);
    if (in.gcount() == 6 && std::memcmp(start, kPngSignature, 8) == 0) return png_header(in);
    return bad("not a PNG or JPEG file (corrupt, truncated or another format)");
}

Status check_image_size(const ImageHeader& header, int max_width, int max_height, int width,
                        int height) {
    const std::string found = std::to_string(header.width) + "x" + std::to_string(header.height);
    if (header.width > max_width || header.height > max_height) {
        return bad("image is " + found + ", larger than the " + std::to_string(max_width) + "x" +
                   std::to_string(max_height) + " maximum (not decoded)");
    }
    if (width > 0 && height > 0 && (header.width != width || header.height != height)) {
        return bad("image is " + found + ", expected " + std::to_string(width) + "x" +
                   std::to_string(height) + " (the size of the intrinsics and the first frame)");
    }
    return Status::ok();
}

}  // namespace df::io
