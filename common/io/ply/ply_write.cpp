// Writing a PointCloud as one PLY vertex element, ASCII or binary little-endian.
#include <cstdio>
#include <cstring>
#include <fstream>

#include "io/ply/ply.hpp"

#if defined(__BYTE_ORDER__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "binary PLY is written from memory as little-endian");
#endif

namespace df::io {

namespace {

std::string header_text(const PointCloud& cloud, const PlyWriteOptions& options) {
    const char* position_type = options.double_positions ? "double" : "float";
    std::string h = "ply\nformat ";
    h += options.format == PlyFormat::kAscii ? "ascii" : "binary_little_endian";
    h += " 1.0\n";
    for (const std::string& c : options.comments) h += "comment " + c + "\n";
    h += "element vertex " + std::to_string(cloud.size()) + "\n";
    for (const char* axis : {"x", "y", "z"})
        h += std::string("property ") + position_type + " " + axis + "\n";
    if (cloud.has_normals()) h += "property float nx\nproperty float ny\nproperty float nz\n";
    if (cloud.has_colours()) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    for (const PointScalar& s : cloud.scalars) h += "property float " + s.name + "\n";
    h += "end_header\n";
    return h;
}

void append_binary(const PointCloud& cloud, bool double_positions, std::string* out) {
    static_assert(sizeof(float) == 4 && sizeof(double) == 8, "PLY float is 4, double 8 bytes");
    const size_t stride = (double_positions ? 24 : 12) + (cloud.has_normals() ? 12 : 0) +
                          (cloud.has_colours() ? 3 : 0) + 4 * cloud.scalars.size();
    const size_t start = out->size();
    out->resize(start + stride * cloud.size());
    char* dst = &(*out)[start];
    for (size_t i = 0; i < cloud.size(); ++i) {
        const Eigen::Vector3d& p = cloud.positions[i];
        if (double_positions) {
            std::memcpy(dst, p.data(), 24);
            dst += 24;
        } else {
            const Eigen::Vector3f f = p.cast<float>();
            std::memcpy(dst, f.data(), 12);
            dst += 12;
        }
        if (cloud.has_normals()) {
            std::memcpy(dst, cloud.normals[i].data(), 12);
            dst += 12;
        }
        if (cloud.has_colours()) {
            std::memcpy(dst, cloud.colours[i].data(), 3);
            dst += 3;
        }
        for (const PointScalar& s : cloud.scalars) {
            std::memcpy(dst, &s.values[i], 4);
            dst += 4;
        }
    }
}

void append_ascii(const PointCloud& cloud, bool double_positions, std::string* out) {
    char field[64];
    auto put = [&](const char* format, auto value, char separator) {
        const int n = std::snprintf(field, sizeof field, format, value);
        out->append(field, static_cast<size_t>(n));
        out->push_back(separator);
    };
    const char* position_format = double_positions ? "%.17g" : "%.9g";
    const bool more = cloud.has_normals() || cloud.has_colours() || !cloud.scalars.empty();
    for (size_t i = 0; i < cloud.size(); ++i) {
        const Eigen::Vector3d& p = cloud.positions[i];
        put(position_format, p.x(), ' ');
        put(position_format, p.y(), ' ');
        put(position_format, p.z(), more ? ' ' : '\n');
        if (cloud.has_normals()) {
            const Eigen::Vector3f& n = cloud.normals[i];
            const bool last = !cloud.has_colours() && cloud.scalars.empty();
            put("%.9g", static_cast<double>(n.x()), ' ');
            put("%.9g", static_cast<double>(n.y()), ' ');
            put("%.9g", static_cast<double>(n.z()), last ? '\n' : ' ');
        }
        if (cloud.has_colours()) {
            const Rgb8& c = cloud.colours[i];
            const bool last = cloud.scalars.empty();
            put("%u", static_cast<unsigned>(c.x()), ' ');
            put("%u", static_cast<unsigned>(c.y()), ' ');
            put("%u", static_cast<unsigned>(c.z()), last ? '\n' : ' ');
        }
        for (size_t k = 0; k < cloud.scalars.size(); ++k) {
            put("%.9g", static_cast<double>(cloud.scalars[k].values[i]),
                k + 1 == cloud.scalars.size() ? '\n' : ' ');
        }
    }
}

}  // namespace

Status write_ply(const std::string& file, const PointCloud& cloud, const PlyWriteOptions& options) {
    const Status valid = cloud.check();
    if (!valid) return valid.with_context("cannot write " + file);
    for (const std::string& c : options.comments) {
        if (c.find_first_of("\r\n") != std::string::npos) {
            return error(StatusCode::kInvalidArgument,
                         "cannot write " + file + ": comment '" + c + "' has a line break");
        }
    }
    std::string bytes = header_text(cloud, options);
    if (options.format == PlyFormat::kAscii) {
        append_ascii(cloud, options.double_positions, &bytes);
    } else {
        append_binary(cloud, options.double_positions, &bytes);
    }
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) return error(StatusCode::kIoError, "cannot write " + file);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return error(StatusCode::kIoError, "error writing " + file);
    return Status::ok();
}

}  // namespace df::io
