// df_gen_params OUT_DIR: writes the C++ parameter structs of the messages the .proto files
// declare as parameter sets (SlamParams' sections in slam.proto, GeosegParams in geoseg.proto,
// InstanceParams in fusion.proto, the detector's fields marked (params_struct)), with their
// defaults, one-line meanings, units and ranges, so that each parameter is declared once, in its
// .proto (docs/slam.md, "Parameters"). Run by the build (common/config/CMakeLists.txt); its
// output is <build>/generated/params/*.hpp, included as "params/slam_params.hpp" and so on.
#include <google/protobuf/descriptor.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/validate.hpp"
#include "detector.pb.h"
#include "fusion.pb.h"
#include "geoseg.pb.h"
#include "options.pb.h"
#include "slam.pb.h"

namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

/// The shortest text that reads back to `v` (0.3f, not 0.300000012f).
std::string float_text(double v, bool single) {
    if (v == std::floor(v) && std::fabs(v) < 1e15) {  // 20.0f, not 2e+01f
        const std::string s = std::to_string(static_cast<long long>(v)) + ".0";
        return single ? s + "f" : s;
    }
    for (int precision = 1; precision <= 17; ++precision) {
        char text[64];
        std::snprintf(text, sizeof text, "%.*g", precision, v);
        const bool same = single ? std::strtof(text, nullptr) == static_cast<float>(v)
                                 : std::strtod(text, nullptr) == v;
        if (!same) continue;
        std::string s = text;
        if (s.find_first_of(".e") == std::string::npos) s += ".0";
        return single ? s + "f" : s;
    }
    throw std::runtime_error("cannot print a default");
}

std::string fail(const FieldDescriptor* f, const std::string& why) {
    throw std::runtime_error(f->full_name() + ": " + why);
}

std::string scalar_type(const FieldDescriptor* f) {
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
            return "float";
        case FieldDescriptor::CPPTYPE_DOUBLE:
            return "double";
        case FieldDescriptor::CPPTYPE_INT32:
            return "int";
        case FieldDescriptor::CPPTYPE_UINT32:
            return "unsigned";
        case FieldDescriptor::CPPTYPE_INT64:
            return "long long";
        case FieldDescriptor::CPPTYPE_UINT64:
            return "std::size_t";
        case FieldDescriptor::CPPTYPE_BOOL:
            return "bool";
        case FieldDescriptor::CPPTYPE_STRING:
            return "std::string";
        case FieldDescriptor::CPPTYPE_MESSAGE:
            return f->message_type()->name();
        default:
            return fail(f, "type not supported in a parameter set");
    }
}

/// One value of a scalar parameter as a C++ literal, from its text (a (defaults) item).
std::string literal(const FieldDescriptor* f, const std::string& text) {
    char* end = nullptr;
    errno = 0;
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
        case FieldDescriptor::CPPTYPE_DOUBLE: {
            const double v = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || !std::isfinite(v))
                fail(f, "default '" + text + "' is not a number");
            return float_text(v, f->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT);
        }
        case FieldDescriptor::CPPTYPE_BOOL:
            if (text != "true" && text != "false") fail(f, "default '" + text + "' is not a bool");
            return text;
        case FieldDescriptor::CPPTYPE_STRING:
            return quoted(text);
        default: {
            const long long v = std::strtoll(text.c_str(), &end, 10);
            if (end == text.c_str() || *end != '\0' || errno != 0)
                fail(f, "default '" + text + "' is not an integer");
            return std::to_string(v);
        }
    }
}

std::string default_of(const FieldDescriptor* f) {
    const auto& options = f->options();
    if (f->is_repeated()) {
        if (!options.HasExtension(df::config::defaults)) return "";
        std::string list;
        std::stringstream items(options.GetExtension(df::config::defaults));
        std::string item;
        while (std::getline(items, item, ','))
            list += (list.empty() ? "" : ", ") + literal(f, item);
        return " = {" + list + "}";
    }
    if (options.HasExtension(df::config::defaults)) fail(f, "(defaults) is for repeated fields");
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) return "";
    if (!f->has_default_value()) fail(f, "a parameter needs [default = ...]");
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_FLOAT:
            return " = " + float_text(f->default_value_float(), true);
        case FieldDescriptor::CPPTYPE_DOUBLE:
            return " = " + float_text(f->default_value_double(), false);
        case FieldDescriptor::CPPTYPE_INT32:
            return " = " + std::to_string(f->default_value_int32());
        case FieldDescriptor::CPPTYPE_UINT32:
            return " = " + std::to_string(f->default_value_uint32()) + "u";
        case FieldDescriptor::CPPTYPE_INT64:
            return " = " + std::to_string(f->default_value_int64()) + "ll";
        case FieldDescriptor::CPPTYPE_UINT64:
            return " = " + std::to_string(f->default_value_uint64()) + "u";
        case FieldDescriptor::CPPTYPE_BOOL:
            return f->default_value_bool() ? " = true" : " = false";
        case FieldDescriptor::CPPTYPE_STRING:
            return " = " + quoted(f->default_value_string());
        default:
            return fail(f, "type not supported in a parameter set");
    }
}

std::string info_of(const FieldDescriptor* f) {
    const auto& options = f->options();
    const df::config::Range r = options.GetExtension(df::config::range);
    const bool has_range = options.HasExtension(df::config::range);
    auto number = [](double v) { return float_text(v, false); };
    std::ostringstream s;
    s << "{" << quoted(f->name()) << ", " << quoted(df::config::unit_of(f)) << ", "
      << quoted(options.GetExtension(df::config::doc)) << ", "
      << quoted(f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE ? "" : df::config::rule_text(f))
      << ", " << (has_range && r.has_min() ? "true" : "false") << ", " << number(r.min()) << ", "
      << (r.min_exclusive() ? "true" : "false") << ", "
      << (has_range && r.has_max() ? "true" : "false") << ", " << number(r.max()) << ", "
      << (r.max_exclusive() ? "true" : "false") << ", "
      << (options.GetExtension(df::config::non_empty) ? "true" : "false") << "}";
    return s.str();
}

/// A comment block: `text` split into lines of about 90 characters.
std::string comment(const std::string& text, const std::string& indent) {
    std::string out, line;
    std::stringstream words(text);
    std::string word;
    while (words >> word) {
        if (!line.empty() && line.size() + word.size() + 1 > 90) {
            out += indent + "/// " + line + "\n";
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) out += indent + "/// " + line + "\n";
    return out;
}

/// The fields of `d` that belong to struct `name`: every field when `name` is the message's own
/// name, else those marked (params_struct) = name (a parameter set inside a service message).
std::vector<const FieldDescriptor*> fields_of(const Descriptor* d, const std::string& name) {
    std::vector<const FieldDescriptor*> fields;
    for (int i = 0; i < d->field_count(); ++i) {
        const FieldDescriptor* f = d->field(i);
        if (name == d->name() || f->options().GetExtension(df::config::params_struct) == name)
            fields.push_back(f);
    }
    return fields;
}

void emit_struct(const Descriptor* d, const std::string& name, const std::string& source,
                 const std::string& indent, std::ostringstream& out) {
    const std::vector<const FieldDescriptor*> fields = fields_of(d, name);
    if (fields.empty()) throw std::runtime_error(d->full_name() + ": no fields for " + name);
    const std::string marked =
        name == d->name() ? "" : ", the fields marked (params_struct) = \"" + name + "\"";
    out << comment(d->full_name() + marked + " (" + source + ").", indent);
    out << indent << "struct " << name << " {\n";
    const std::string in = indent + "    ";
    // The nested messages its fields use become nested structs.
    for (int i = 0; i < d->nested_type_count(); ++i) {
        const Descriptor* nested = d->nested_type(i);
        bool used = false;
        for (const FieldDescriptor* f : fields) used = used || f->message_type() == nested;
        if (!used) continue;
        emit_struct(nested, nested->name(), source, in, out);
        out << "\n";
    }
    for (const FieldDescriptor* f : fields) {
        const auto& options = f->options();
        if (!options.HasExtension(df::config::doc)) fail(f, "a parameter needs (doc) = \"...\"");
        std::string what = options.GetExtension(df::config::doc);
        const std::string unit = df::config::unit_of(f);
        const std::string allowed = df::config::allowed_text(f);
        if (!unit.empty()) what += " [" + unit + "]";
        if (!allowed.empty()) what += "; allowed: " + allowed;
        out << comment(what, in);
        const std::string type = scalar_type(f);
        out << in << (f->is_repeated() ? "std::vector<" + type + ">" : type) << " " << f->name()
            << default_of(f) << ";\n";
    }
    const size_t n = fields.size();
    out << "\n" << in << "static constexpr FieldInfo kFields[" << n << "] = {\n";
    for (const FieldDescriptor* f : fields) out << in << "    " << info_of(f) << ",\n";
    out << in << "};\n";
    for (const char* constness : {"", " const"}) {
        out << in << "/// Calls f(kFields[i], field) for every field, in declaration order.\n";
        out << in << "template <class F>\n"
            << in << "void for_each_field(F&& f)" << constness << " {\n";
        for (size_t i = 0; i < n; ++i)
            out << in << "    f(kFields[" << i << "], " << fields[i]->name() << ");\n";
        out << in << "}\n";
    }
    out << indent << "};\n";
}

/// One generated header: the messages of one .proto that are parameter sets.
struct Unit {
    std::string file;   ///< under OUT_DIR/params/
    std::string proto;  ///< for the comments
    std::string ns;     ///< df::params::<ns>
    /// Each message with the name of the struct made of it (the message's own name: all its
    /// fields; another name: its fields marked (params_struct) with that name).
    std::vector<std::pair<const Descriptor*, std::string>> messages;
};

std::string header(const Unit& unit) {
    std::ostringstream out;
    out << "#pragma once\n"
           "// Generated by df_gen_params (common/config/gen_params.cpp) from\n"
           "// "
        << unit.proto
        << ": do not edit; declare parameters there.\n"
           "#include <cstddef>\n#include <string>\n#include <vector>\n\n#include "
           "\"params/field_info.hpp\"\n\n"
           "namespace df::params::"
        << unit.ns << " {\n\n";
    for (const auto& [d, name] : unit.messages) {
        emit_struct(d, name, unit.proto, "", out);
        out << "\n";
    }
    out << "}  // namespace df::params::" << unit.ns << "\n";
    return out.str();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: df_gen_params OUT_DIR (writes OUT_DIR/params/*.hpp)\n");
        return 2;
    }
    std::vector<Unit> units;
    Unit slam{"slam_params.hpp", "common/config/slam.proto", "slam", {}};
    const Descriptor* top = df::config::SlamParams::descriptor();
    for (int i = 0; i < top->nested_type_count(); ++i)
        slam.messages.emplace_back(top->nested_type(i), top->nested_type(i)->name());
    units.push_back(slam);
    units.push_back({"geoseg_params.hpp",
                     "common/config/geoseg.proto",
                     "geoseg",
                     {{df::config::GeosegParams::descriptor(), "GeosegParams"}}});
    units.push_back({"fusion_params.hpp",
                     "common/config/fusion.proto",
                     "fusion",
                     {{df::config::InstanceParams::descriptor(), "InstanceParams"},
                      {df::config::ClassParams::descriptor(), "ClassParams"},
                      {df::config::FusionServiceConfig::descriptor(), "JoinParams"}}});
    units.push_back({"detector_params.hpp",
                     "common/config/detector.proto",
                     "detector",
                     {{df::config::DetectorServiceConfig::descriptor(), "DetectorParams"}}});
    for (const Unit& unit : units) {
        std::string text;
        try {
            text = header(unit);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "df_gen_params: %s\n", e.what());
            return 1;
        }
        const std::string path = std::string(argv[1]) + "/params/" + unit.file;
        std::ofstream file(path + ".tmp");
        file << text;
        file.close();
        if (!file || std::rename((path + ".tmp").c_str(), path.c_str()) != 0) {
            std::fprintf(stderr, "df_gen_params: cannot write %s\n", path.c_str());
            return 1;
        }
    }
    return 0;
}
