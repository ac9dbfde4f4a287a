// The PLY header: "ply", "format", "comment", "element", "property" lines up to "end_header".
#include "io/ply/ply_header.hpp"

#include <sstream>

namespace df::io::ply_detail {

bool parse_scalar_type(const std::string& name, Scalar* type) {
    static const struct {
        const char* name;
        Scalar type;
    } kTypes[] = {
        {"char", Scalar::kInt8},      {"int8", Scalar::kInt8},       {"uchar", Scalar::kUint8},
        {"uint8", Scalar::kUint8},    {"short", Scalar::kInt16},     {"int16", Scalar::kInt16},
        {"ushort", Scalar::kUint16},  {"uint16", Scalar::kUint16},   {"int", Scalar::kInt32},
        {"int32", Scalar::kInt32},    {"uint", Scalar::kUint32},     {"uint32", Scalar::kUint32},
        {"float", Scalar::kFloat32},  {"float32", Scalar::kFloat32}, {"double", Scalar::kFloat64},
        {"float64", Scalar::kFloat64}};
    for (const auto& t : kTypes) {
        if (name == t.name) {
            *type = t.type;
            return true;
        }
    }
    return false;
}

size_t scalar_size(Scalar type) {
    switch (type) {
        case Scalar::kInt8:
        case Scalar::kUint8:
            return 1;
        case Scalar::kInt16:
        case Scalar::kUint16:
            return 2;
        case Scalar::kInt32:
        case Scalar::kUint32:
        case Scalar::kFloat32:
            return 4;
        case Scalar::kFloat64:
            return 8;
    }
    return 0;
}

std::string strip_cr(std::string line) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
}

namespace {

/// Parses the rest of a "property ..." line into `p`; false if it does not fit the grammar.
bool parse_property(std::istringstream& in, Property* p) {
    std::string type;
    in >> type;
    if (type == "list") {
        std::string count_type, item_type;
        in >> count_type >> item_type >> p->name;
        p->is_list = true;
        return parse_scalar_type(count_type, &p->count_type) &&
               parse_scalar_type(item_type, &p->type) && !p->name.empty();
    }
    in >> p->name;
    return parse_scalar_type(type, &p->type) && !p->name.empty();
}

}  // namespace

Result<Header> parse_header(const std::string& file, const std::string& bytes) {
    Header header;
    size_t pos = 0;
    int line_no = 0;
    bool format_seen = false;
    auto fail = [&](const std::string& what) {
        return error(StatusCode::kInvalidArgument,
                     file + ":" + std::to_string(line_no) + ": " + what);
    };
    while (true) {
        const size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) {
            return error(StatusCode::kInvalidArgument,
                         file + ": PLY header has no 'end_header' line (truncated or not PLY)");
        }
        const std::string line = strip_cr(bytes.substr(pos, end - pos));
        pos = end + 1;
        ++line_no;
        std::istringstream in(line);
        std::string keyword;
        in >> keyword;
        if (line_no == 1) {
            if (keyword != "ply") return fail("not a PLY file (first line is not 'ply')");
            continue;
        }
        if (keyword.empty() || keyword == "obj_info") continue;
        if (keyword == "comment") {
            const size_t start = line.find_first_not_of(" \t", line.find("comment") + 7);
            header.comments.push_back(start == std::string::npos ? "" : line.substr(start));
        } else if (keyword == "format") {
            std::string format;
            in >> format;
            if (format == "ascii") {
                header.binary = false;
            } else if (format == "binary_little_endian") {
                header.binary = true;
            } else if (format == "binary_big_endian") {
                return fail("binary_big_endian PLY is not supported (convert to little endian)");
            } else {
                return fail("unknown PLY format '" + format + "'");
            }
            format_seen = true;
        } else if (keyword == "element") {
            Element e;
            long long count = -1;
            in >> e.name >> count;
            if (e.name.empty() || !in || count < 0) {
                return fail("expected 'element <name> <count>', found '" + line + "'");
            }
            e.count = static_cast<size_t>(count);
            header.elements.push_back(e);
        } else if (keyword == "property") {
            if (header.elements.empty()) return fail("property before any element");
            Property p;
            if (!parse_property(in, &p)) {
                return fail(p.is_list ? "expected 'property list <count type> <item type> <name>', "
                                        "found '" +
                                            line + "'"
                                      : "expected 'property <type> <name>' with a PLY type (float, "
                                        "double, uchar, int...), found '" +
                                            line + "'");
            }
            header.elements.back().properties.push_back(p);
        } else if (keyword == "end_header") {
            break;
        } else {
            return fail("unexpected header line '" + line + "'");
        }
    }
    if (!format_seen) return fail("PLY header has no 'format' line");
    header.data_offset = pos;
    header.data_line = line_no + 1;
    return header;
}

}  // namespace df::io::ply_detail
