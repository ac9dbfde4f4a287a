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

std::set<std::string> proto_names() {
    std::set<std::string> names;
    const auto* top = config::SlamParams::descriptor();
    for (int s = 0; s < top->field_count(); ++s) {
        const FieldDescriptor* section = top->field(s);
        const auto* sub = section->message_type();
        for (int i = 0; i < sub->field_count(); ++i)
            names.insert(section->name() + "." + sub->field(i)->name());
    }
    return names;
}

}  // namespace

Status apply(const config::SlamParams& params, slam::SystemConfig* config) {
    std::map<std::string, slam::Parameter> table;
    for (slam::Parameter& p : slam::parameters(config)) table.emplace(p.name, p);
    const Reflection* top_r = params.GetReflection();
    std::vector<const FieldDescriptor*> sections;
    top_r->ListFields(params, &sections);
    for (const FieldDescriptor* section : sections) {
        const Message& sub = top_r->GetMessage(params, section);
        std::vector<const FieldDescriptor*> fields;
        sub.GetReflection()->ListFields(sub, &fields);
        for (const FieldDescriptor* f : fields) {
            const std::string name = section->name() + "." + f->name();
            auto it = table.find(name);
            if (it == table.end()) {
                return error(StatusCode::kInvalidArgument,
                             "slam." + name + " is in slam.proto but not a SLAM parameter");
            }
            DF_RETURN_IF_ERROR(slam::set_value(it->second, field_text(sub, f)));
        }
    }
    return Status::ok();
}

config::SlamParams to_params(const slam::SystemConfig& config) {
    slam::SystemConfig copy = config;
    std::string text;
    for (const slam::Parameter& p : slam::parameters(&copy)) {
        const size_t dot = p.name.find('.');
        std::string value = slam::value_text(p);
        if (std::holds_alternative<std::vector<int>*>(p.value) ||
            std::holds_alternative<std::vector<float>*>(p.value)) {
            value = "[" + value + "]";
        }
        text += p.name.substr(0, dot) + " { " + p.name.substr(dot + 1) + ": " + value + " } ";
    }
    config::SlamParams params;
    google::protobuf::TextFormat::MergeFromString(text, &params);
    return params;
}

std::string params_table(const slam::SystemConfig& config) {
    slam::SystemConfig copy = config;
    const auto* top = config::SlamParams::descriptor();
    std::string out =
        "# slam { <section> { <field>: value } } in a service config, or\n"
        "# --set 'slam { <section> { <field>: value } }'\n"
        "# name                                     default    allowed [unit]  meaning\n";
    for (const slam::Parameter& p : slam::parameters(&copy)) {
        const size_t dot = p.name.find('.');
        const FieldDescriptor* section = top->FindFieldByName(p.name.substr(0, dot));
        const FieldDescriptor* field =
            section ? section->message_type()->FindFieldByName(p.name.substr(dot + 1)) : nullptr;
        std::string allowed = field ? config::allowed_text(field) : "";
        const std::string unit = field ? config::unit_of(field) : "";
        if (!unit.empty()) allowed += (allowed.empty() ? "" : " ") + ("[" + unit + "]");
        char line[512];
        std::snprintf(line, sizeof line, "%-42s %-10s %-24s %s\n", p.name.c_str(),
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
