// Reading the vertex element of a PLY file: the header decides how to walk the data; elements
// before the vertices are stepped over, nothing after them is read.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "io/ply/ply.hpp"
#include "io/ply/ply_header.hpp"

namespace df::io {

namespace {

using ply_detail::Element;
using ply_detail::Header;
using ply_detail::Property;
using ply_detail::read_scalar;
using ply_detail::scalar_size;

/// Which vertex property (index into Element::properties) fills what; -1 if absent.
struct VertexLayout {
    int xyz[3] = {-1, -1, -1};
    int normal[3] = {-1, -1, -1};  ///< all set or all -1
    int colour[3] = {-1, -1, -1};  ///< all set or all -1
    std::vector<int> scalars;      ///< the other scalar properties, in file order
};

Result<VertexLayout> layout_of(const std::string& file, const Element& vertex) {
    VertexLayout l;
    static const char* const kNames[9] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"};
    int found[9] = {-1, -1, -1, -1, -1, -1, -1, -1, -1};
    for (size_t i = 0; i < vertex.properties.size(); ++i) {
        const Property& p = vertex.properties[i];
        for (int k = 0; k < 9; ++k) {
            if (p.name != kNames[k]) continue;
            if (p.is_list && k < 3) {
                return error(StatusCode::kInvalidArgument, file + ": vertex property '" + p.name +
                                                               "' is a list, expected a number");
            }
            if (!p.is_list) found[k] = static_cast<int>(i);
        }
    }
    if (found[0] < 0 || found[1] < 0 || found[2] < 0) {
        return error(StatusCode::kInvalidArgument,
                     file + ": element 'vertex' lacks a property x, y or z");
    }
    std::copy(found, found + 3, l.xyz);
    const bool normals = found[3] >= 0 && found[4] >= 0 && found[5] >= 0;
    const bool colours = found[6] >= 0 && found[7] >= 0 && found[8] >= 0;
    if (normals) std::copy(found + 3, found + 6, l.normal);
    if (colours) std::copy(found + 6, found + 9, l.colour);
    for (size_t i = 0; i < vertex.properties.size(); ++i) {
        const int ii = static_cast<int>(i);
        const bool used = std::find(l.xyz, l.xyz + 3, ii) != l.xyz + 3 ||
                          std::find(l.normal, l.normal + 3, ii) != l.normal + 3 ||
                          std::find(l.colour, l.colour + 3, ii) != l.colour + 3;
        if (!used && !vertex.properties[i].is_list) l.scalars.push_back(ii);
    }
    return l;
}

/// An empty cloud with the attributes `l` fills, room for `capacity` points.
PointCloud empty_cloud(const Element& vertex, const VertexLayout& l, size_t capacity) {
    PointCloud cloud;
    cloud.positions.reserve(capacity);
    if (l.normal[0] >= 0) cloud.normals.reserve(capacity);
    if (l.colour[0] >= 0) cloud.colours.reserve(capacity);
    for (int k : l.scalars) {
        cloud.scalars.push_back({vertex.properties[static_cast<size_t>(k)].name, {}});
        cloud.scalars.back().values.reserve(capacity);
    }
    return cloud;
}

uint8_t to_channel(double v) {
    if (!(v > 0)) return 0;
    if (v >= 255) return 255;
    return static_cast<uint8_t>(std::lround(v));
}

/// Appends the vertex whose property values are `row` (indexed like the properties), or counts
/// it as skipped if a coordinate is not finite.
void keep_vertex(const VertexLayout& l, const std::vector<double>& row, PointCloud* cloud,
                 size_t* skipped_nonfinite) {
    const Eigen::Vector3d p(row[l.xyz[0]], row[l.xyz[1]], row[l.xyz[2]]);
    if (!p.allFinite()) {
        ++*skipped_nonfinite;
        return;
    }
    cloud->positions.push_back(p);
    if (l.normal[0] >= 0) {
        cloud->normals.emplace_back(static_cast<float>(row[l.normal[0]]),
                                    static_cast<float>(row[l.normal[1]]),
                                    static_cast<float>(row[l.normal[2]]));
    }
    if (l.colour[0] >= 0) {
        cloud->colours.emplace_back(to_channel(row[l.colour[0]]), to_channel(row[l.colour[1]]),
                                    to_channel(row[l.colour[2]]));
    }
    for (size_t k = 0; k < l.scalars.size(); ++k)
        cloud->scalars[k].values.push_back(static_cast<float>(row[l.scalars[k]]));
}

/// Bytes of one instance of `e` in a binary file, lists counted as empty.
size_t min_binary_size(const Element& e) {
    size_t size = 0;
    for (const Property& p : e.properties)
        size += p.is_list ? scalar_size(p.count_type) : scalar_size(p.type);
    return size;
}

/// Walks one instance of `e` from `*pos`, putting scalar values into `row` (if not null).
/// Returns false if the data ends inside it; sets `problem` if it is malformed.
bool read_binary_instance(const std::string& bytes, const Element& e, size_t* pos,
                          std::vector<double>* row, std::string* problem) {
    for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        size_t items = 1;
        if (p.is_list) {
            const size_t count_size = scalar_size(p.count_type);
            if (*pos + count_size > bytes.size()) return false;
            const double c = read_scalar(bytes.data() + *pos, p.count_type);
            if (!(c >= 0)) {
                *problem = "list '" + p.name + "' has a negative length";
                return true;
            }
            if (c > static_cast<double>(bytes.size())) return false;
            items = static_cast<size_t>(c);
            *pos += count_size;
        }
        const size_t size = scalar_size(p.type) * items;
        if (*pos + size > bytes.size()) return false;
        if (row && !p.is_list) (*row)[k] = read_scalar(bytes.data() + *pos, p.type);
        *pos += size;
    }
    return true;
}

Result<PointCloud> read_binary(const std::string& file, const std::string& bytes,
                               const Header& header, PlyReadInfo* info) {
    size_t pos = header.data_offset;
    for (const Element& e : header.elements) {
        const bool is_vertex = e.name == "vertex";
        const bool has_list = std::any_of(e.properties.begin(), e.properties.end(),
                                          [](const Property& p) { return p.is_list; });
        const size_t min_size = min_binary_size(e);
        const size_t left = bytes.size() - pos;
        if (!is_vertex && !has_list) {  // fixed-size instances: step over all at once
            if (min_size > 0 && e.count > left / min_size) {
                return error(StatusCode::kIoError, file + ": file ends inside element '" + e.name +
                                                       "' " + std::to_string(left / min_size) +
                                                       " of " + std::to_string(e.count) +
                                                       " (truncated binary PLY?)");
            }
            pos += min_size * e.count;
            continue;
        }
        VertexLayout layout;
        PointCloud cloud;
        if (is_vertex) {
            auto found = layout_of(file, e);
            if (!found) return found.status();
            layout = *found;
            cloud = empty_cloud(e, layout, std::min(e.count, left / std::max<size_t>(1, min_size)));
        }
        std::vector<double> row(e.properties.size());
        for (size_t n = 0; n < e.count; ++n) {
            std::string problem;
            if (!read_binary_instance(bytes, e, &pos, is_vertex ? &row : nullptr, &problem)) {
                return error(StatusCode::kIoError, file + ": file ends inside element '" + e.name +
                                                       "' " + std::to_string(n) + " of " +
                                                       std::to_string(e.count) +
                                                       " (truncated binary PLY?)");
            }
            if (!problem.empty()) {
                return error(StatusCode::kInvalidArgument, file + ": element '" + e.name + "' " +
                                                               std::to_string(n) + ": " + problem);
            }
            if (is_vertex) keep_vertex(layout, row, &cloud, &info->skipped_nonfinite);
        }
        if (is_vertex) return cloud;  // nothing after the vertices is needed
    }
    return error(StatusCode::kInternal, file + ": no vertex element");  // checked by the caller
}

/// The next line of `bytes` from `*pos` as [begin, end) without its line break; false at the end.
bool next_line(const std::string& bytes, size_t* pos, const char** begin, const char** end) {
    if (*pos >= bytes.size()) return false;
    size_t stop = bytes.find('\n', *pos);
    if (stop == std::string::npos) stop = bytes.size();
    *begin = bytes.data() + *pos;
    *end = bytes.data() + stop;
    if (*end > *begin && (*end)[-1] == '\r') --*end;
    *pos = stop + 1;
    return true;
}

struct Token {
    const char* begin;
    const char* end;
    std::string str() const { return std::string(begin, end); }
};

void split(const char* begin, const char* end, std::vector<Token>* tokens) {
    tokens->clear();
    const char* p = begin;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
        const char* start = p;
        while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
        if (p > start) tokens->push_back({start, p});
    }
}

/// The number in `t`; false if `t` is not entirely a number. The data ends in a '\0' or a line
/// break, so strtod stops at the token's end.
bool parse_number(const Token& t, double* value) {
    char* stop = nullptr;
    *value = std::strtod(t.begin, &stop);
    return stop == t.end;
}

/// Parses one vertex line into `row`; "" or what is wrong.
std::string parse_vertex_line(const Element& e, const std::vector<Token>& tokens,
                              std::vector<double>* row) {
    size_t t = 0;
    for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        size_t items = 1;
        if (p.is_list) {
            double count = 0;
            if (t < tokens.size() &&
                (!parse_number(tokens[t], &count) || !(count >= 0) || count != std::floor(count))) {
                return "expected a list length for " + p.name + ", found '" + tokens[t].str() + "'";
            }
            ++t;
            items = count < 1e9 ? static_cast<size_t>(count) : tokens.size();
        }
        if (t + items > tokens.size()) {
            return "expected " + std::to_string(e.properties.size()) + " values, found " +
                   std::to_string(tokens.size());
        }
        if (!p.is_list && !parse_number(tokens[t], &(*row)[k])) {
            return "expected a number for " + p.name + ", found '" + tokens[t].str() + "'";
        }
        t += items;
    }
    return "";
}

Result<PointCloud> read_ascii(const std::string& file, const std::string& bytes,
                              const Header& header, PlyReadInfo* info) {
    size_t pos = header.data_offset;
    int line_no = header.data_line - 1;
    std::vector<Token> tokens;
    for (const Element& e : header.elements) {
        const bool is_vertex = e.name == "vertex";
        VertexLayout layout;
        PointCloud cloud;
        if (is_vertex) {
            auto found = layout_of(file, e);
            if (!found) return found.status();
            layout = *found;
            cloud = empty_cloud(e, layout, std::min(e.count, (bytes.size() - pos) / 2));
        }
        std::vector<double> row(e.properties.size());
        for (size_t n = 0; n < e.count;) {
            const char *begin = nullptr, *end = nullptr;
            if (!next_line(bytes, &pos, &begin, &end)) {
                return error(StatusCode::kIoError, file + ": file ends after " + std::to_string(n) +
                                                       " of " + std::to_string(e.count) + " '" +
                                                       e.name + "' lines");
            }
            ++line_no;
            split(begin, end, &tokens);
            if (tokens.empty()) continue;  // tolerate blank lines
            if (is_vertex) {
                const std::string problem = parse_vertex_line(e, tokens, &row);
                if (!problem.empty()) {
                    return error(StatusCode::kInvalidArgument,
                                 file + ":" + std::to_string(line_no) + ": vertex " +
                                     std::to_string(n) + ": " + problem);
                }
                keep_vertex(layout, row, &cloud, &info->skipped_nonfinite);
            }
            ++n;
        }
        if (is_vertex) return cloud;
    }
    return error(StatusCode::kInternal, file + ": no vertex element");  // checked by the caller
}

}  // namespace

Result<PointCloud> read_ply(const std::string& file, PlyReadInfo* info) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return error(StatusCode::kNotFound, file + ": cannot open PLY file");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return error(StatusCode::kIoError, file + ": cannot read PLY file");
    auto header = ply_detail::parse_header(file, bytes);
    if (!header) return header.status();
    const bool has_vertex = std::any_of(header->elements.begin(), header->elements.end(),
                                        [](const Element& e) { return e.name == "vertex"; });
    if (!has_vertex) {
        return error(StatusCode::kInvalidArgument, file + ": PLY header has no 'element vertex'");
    }
    PlyReadInfo local;
    PlyReadInfo* out = info ? info : &local;
    *out = PlyReadInfo{};
    out->format = header->binary ? PlyFormat::kBinaryLittleEndian : PlyFormat::kAscii;
    out->comments = header->comments;
    return header->binary ? read_binary(file, bytes, *header, out)
                          : read_ascii(file, bytes, *header, out);
}

}  // namespace df::io
