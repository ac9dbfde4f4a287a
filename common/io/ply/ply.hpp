#pragma once
/// Point clouds as PLY files, the one PLY module of the project (generator models, SLAM maps,
/// evaluation). A cloud is its vertex element: x y z, and optionally nx ny nz, red green blue and
/// any number of extra named float properties (radius, confidence...).
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::io {

using Rgb8 = Eigen::Matrix<uint8_t, 3, 1>;  ///< red, green, blue, 0..255

/// A named per-point property beyond position, normal and colour.
struct PointScalar {
    std::string name;           ///< PLY property name: no spaces, not a name the cloud uses
    std::vector<float> values;  ///< one per point
};

/// Points with optional per-point attributes; each non-empty attribute has one entry per point.
/// Positions are double so that double PLY files and computed clouds keep their precision; they
/// are written as float unless asked otherwise.
struct PointCloud {
    std::vector<Eigen::Vector3d> positions;  ///< x y z, in the file's units (metres here)
    std::vector<Eigen::Vector3f> normals;    ///< nx ny nz: empty, or one (unit) normal per point
    std::vector<Rgb8> colours;               ///< red green blue: empty, or one per point
    std::vector<PointScalar> scalars;        ///< extra properties, written in this order

    size_t size() const { return positions.size(); }
    bool empty() const { return positions.empty(); }
    bool has_normals() const { return !normals.empty(); }
    bool has_colours() const { return !colours.empty(); }

    /// The values of the extra property `name`, or nullptr if the cloud has none of that name.
    const std::vector<float>* scalar(const std::string& name) const;
    std::vector<float>* scalar(const std::string& name);
    /// The values of the extra property `name`, added (empty) at the end if not there yet.
    std::vector<float>& add_scalar(const std::string& name);

    /// kInvalidArgument if an attribute's length differs from the number of points, or an extra
    /// property's name is empty, has white space, repeats, or is one of x y z nx ny nz red green
    /// blue.
    Status check() const;
};

enum class PlyFormat { kAscii, kBinaryLittleEndian };

struct PlyWriteOptions {
    PlyFormat format = PlyFormat::kBinaryLittleEndian;
    bool double_positions = false;      ///< x y z as double (exact); float otherwise
    std::vector<std::string> comments;  ///< one "comment" header line each, after "format"
};

/// Writes `cloud` to `file` (overwritten) as one vertex element: "x y z" (float or double), then
/// "nx ny nz" (float) if it has normals, "red green blue" (uchar) if it has colours, then its
/// extra properties (float). Binary files take 12 (24) + 12 + 3 + 4 per extra bytes a point.
/// kInvalidArgument if cloud.check() fails or a comment has a line break; kIoError naming the file
/// if it cannot be written.
Status write_ply(const std::string& file, const PointCloud& cloud,
                 const PlyWriteOptions& options = {});

/// What read_ply saw besides the points.
struct PlyReadInfo {
    PlyFormat format = PlyFormat::kAscii;
    std::vector<std::string> comments;  ///< text of the "comment" header lines
    size_t skipped_nonfinite = 0;       ///< vertices dropped: NaN or infinite x, y or z
};

/// Reads the vertex element of a PLY file ("format ascii 1.0" or "binary_little_endian 1.0").
/// Every property may have any PLY scalar type (char...double, int8...float64); the vertex
/// element may come after others (faces...), which are skipped, as are list properties of the
/// vertices. x y z are required; nx ny nz become normals and red green blue colours (rounded and
/// clamped to 0..255) when all three are there; every other scalar vertex property becomes an
/// extra property in file order. Vertices with a non-finite coordinate are dropped (counted in
/// `info`). Errors name the file and what is wrong (header line, vertex number and line,
/// truncation): kNotFound if it cannot be opened, kIoError if it is cut short, kInvalidArgument
/// if malformed or big-endian.
Result<PointCloud> read_ply(const std::string& file, PlyReadInfo* info = nullptr);

}  // namespace df::io
