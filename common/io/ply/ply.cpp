// PointCloud: its extra properties and the consistency check the writer relies on.
#include "io/ply/ply.hpp"

#include <algorithm>

namespace df::io {

namespace {

bool reserved_name(const std::string& name) {
    static const char* const kNames[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"};
    return std::any_of(std::begin(kNames), std::end(kNames),
                       [&](const char* n) { return name == n; });
}

std::string count_mismatch(const std::string& what, size_t n, size_t points) {
    return what + " has " + std::to_string(n) + " values for " + std::to_string(points) + " points";
}

}  // namespace

const std::vector<float>* PointCloud::scalar(const std::string& name) const {
    for (const PointScalar& s : scalars)
        if (s.name == name) return &s.values;
    return nullptr;
}

std::vector<float>* PointCloud::scalar(const std::string& name) {
    for (PointScalar& s : scalars)
        if (s.name == name) return &s.values;
    return nullptr;
}

std::vector<float>& PointCloud::add_scalar(const std::string& name) {
    if (std::vector<float>* existing = scalar(name)) return *existing;
    scalars.push_back({name, {}});
    return scalars.back().values;
}

Status PointCloud::check() const {
    const size_t n = positions.size();
    if (!normals.empty() && normals.size() != n)
        return error(StatusCode::kInvalidArgument, count_mismatch("normals", normals.size(), n));
    if (!colours.empty() && colours.size() != n)
        return error(StatusCode::kInvalidArgument, count_mismatch("colours", colours.size(), n));
    for (size_t k = 0; k < scalars.size(); ++k) {
        const PointScalar& s = scalars[k];
        if (s.name.empty() || s.name.find_first_of(" \t\r\n") != std::string::npos) {
            return error(StatusCode::kInvalidArgument,
                         "extra property name '" + s.name + "' is empty or has white space");
        }
        if (reserved_name(s.name)) {
            return error(StatusCode::kInvalidArgument, "extra property '" + s.name +
                                                           "' clashes with a position, normal or " +
                                                           "colour property");
        }
        for (size_t j = 0; j < k; ++j) {
            if (scalars[j].name == s.name)
                return error(StatusCode::kInvalidArgument,
                             "extra property '" + s.name + "' appears twice");
        }
        if (s.values.size() != n) {
            return error(StatusCode::kInvalidArgument,
                         count_mismatch("extra property '" + s.name + "'", s.values.size(), n));
        }
    }
    return Status::ok();
}

}  // namespace df::io
