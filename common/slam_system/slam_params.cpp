#include "slam_system/slam_params.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>
#include <google/protobuf/text_format.h>

#include <map>
#include <set>
#include <variant>

#include "config/validate.hpp"
#include "slam_system/parameters.hpp"

namespace df::slam {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

/// Text of a scalar field (or of the repeated field's elements, comma separated), in the form
/// slam::set_value reads.
std::string field_text(const Message& m, const FieldDescriptor* f) {
    const Reflection* r = m.GetReflection();
    auto one = [&](int i) -> std::string {
        const bool rep = f->is_repeated();
        switch (f->cpp_type()) {
            case FieldDescriptor::CPPTYPE_FLOAT: {
                char buffer[64];
                snprintf(buffer, sizeof buffer, "%.9g",
                         rep ? r->GetRepeatedFloat(m, f, i) : r->GetFloat(m, f));
                return buffer;
            }
            case FieldDescriptor::CPPTYPE_DOUBLE: {
                char buffer[64];
                snprintf(buffer, sizeof buffer, "%.17g",
                         rep ? r->GetRepeatedDouble(m, f, i) : r->GetDouble(m, f));
                return buffer;
            }
            case FieldDescriptor::CPPTYPE_INT32:
                return std::to_string(rep ? r->GetRepeatedInt32(m, f, i) : r->GetInt32(m, f));
            case FieldDescriptor::CPPTYPE_UINT64:
                return std::to_string(rep ? r->GetRepeatedUInt64(m, f, i) : r->GetUInt64(m, f));
            case FieldDescriptor::CPPTYPE_UINT32:
                return std::to_string(rep ? r->GetRepeatedUInt32(m, f, i) : r->GetUInt32(m, f));
            case FieldDescriptor::CPPTYPE_BOOL:
                return (rep ? r->GetRepeatedBool(m, f, i) : r->GetBool(m, f)) ? "true" : "false";
            default:
                return "";
        }
    };
    if (!f->is_repeated()) return one(0);
    std::string text;
    for (int i = 0; i < r->FieldSize(m, f); ++i) text += (i ? "," : "") + one(i);
    return text;
}

void add_names(const google::protobuf::Descriptor* d, const std::string& prefix,
               std::set<std::string>* names) {
    for (int i = 0; i < d->field_count(); ++i) {
        const FieldDescriptor* f = d->field(i);
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
            add_names(f->message_type(), prefix + f->name() + ".", names);
        } else {
            names->insert(prefix + f->name());
        }
    }
}

std::set<std::string> proto_names() {
    std::set<std::string> names;
    add_names(config::SlamParams::descriptor(), "", &names);
    return names;
}

/// Sets every field set in `m` (nested messages walked) on the parameter of its dotted name.
Status apply_fields(const Message& m, const std::string& prefix,
                    const std::map<std::string, slam::Parameter>& table) {
    std::vector<const FieldDescriptor*> fields;
    m.GetReflection()->ListFields(m, &fields);
    for (const FieldDescriptor* f : fields) {
        const std::string name = prefix + f->name();
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
            DF_RETURN_IF_ERROR(apply_fields(m.GetReflection()->GetMessage(m, f), name + ".", table));
            continue;
        }
        auto it = table.find(name);
        if (it == table.end()) {
            return error(StatusCode::kInvalidArgument,
                         "slam." + name + " is in slam.proto but not a SLAM parameter");
        }
        DF_RETURN_IF_ERROR(slam::set_value(it->second, field_text(m, f)));
    }
    return Status::ok();
}

/// The descriptor of the field a dotted parameter name ("objects.association.min_overlap")
/// names, or nullptr.
const FieldDescriptor* field_named(const std::string& name) {
    const google::protobuf::Descriptor* d = config::SlamParams::descriptor();
    const FieldDescriptor* f = nullptr;
    size_t begin = 0;
    while (d != nullptr) {
        const size_t dot = name.find('.', begin);
        f = d->FindFieldByName(name.substr(begin, dot == std::string::npos ? dot : dot - begin));
        if (f == nullptr || dot == std::string::npos) return f;
        d = f->message_type();
        begin = dot + 1;
    }
    return nullptr;
}

}  // namespace

Status apply(const config::SlamParams& params, slam::SystemConfig* config) {
    std::map<std::string, slam::Parameter> table;
    for (slam::Parameter& p : slam::parameters(config)) table.emplace(p.name, p);
    return apply_fields(params, "", table);
}

config::SlamParams to_params(const slam::SystemConfig& config) {
    slam::SystemConfig copy = config;
    std::string text;
    for (const slam::Parameter& p : slam::parameters(&copy)) {
        std::string value = slam::value_text(p);
        if (std::holds_alternative<std::vector<int>*>(p.value) ||
            std::holds_alternative<std::vector<float>*>(p.value)) {
            value = "[" + value + "]";
        }
        // "a.b.c" as "a { b { c: value } }"
        std::string name = p.name, closing;
        for (size_t dot; (dot = name.find('.')) != std::string::npos; name.erase(0, dot + 1)) {
            text += name.substr(0, dot) + " { ";
            closing += "} ";
        }
        text += name + ": " + value + " " + closing;
    }
    config::SlamParams params;
    google::protobuf::TextFormat::MergeFromString(text, &params);
    return params;
}

std::string params_table(const slam::SystemConfig& config) {
    slam::SystemConfig copy = config;
    std::string out =
        "# slam { <section> { <field>: value } } in a service config, or\n"
        "# --set 'slam { <section> { <field>: value } }'\n"
        "# name                                           default    allowed [unit]  meaning\n";
    for (const slam::Parameter& p : slam::parameters(&copy)) {
        const FieldDescriptor* field = field_named(p.name);
        std::string allowed = field ? config::allowed_text(field) : "";
        const std::string unit = field ? config::unit_of(field) : "";
        if (!unit.empty()) allowed += (allowed.empty() ? "" : " ") + ("[" + unit + "]");
        char line[512];
        std::snprintf(line, sizeof line, "%-48s %-10s %-24s %s\n", p.name.c_str(),
                      slam::value_text(p).c_str(), allowed.empty() ? "-" : allowed.c_str(),
                      p.meaning.c_str());
        out += line;
    }
    return out;
}

std::vector<std::string> mismatches() {
    slam::SystemConfig config;
    std::set<std::string> table;
    for (const slam::Parameter& p : slam::parameters(&config)) table.insert(p.name);
    const std::set<std::string> proto = proto_names();
    std::vector<std::string> out;
    for (const std::string& n : proto)
        if (!table.count(n)) out.push_back("proto only: " + n);
    for (const std::string& n : table)
        if (!proto.count(n)) out.push_back("table only: " + n);
    return out;
}

}  // namespace df::slam
