#include "slam_system/slam_params.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>
#include <google/protobuf/text_format.h>

#include <set>
#include <variant>

#include "config/apply_params.hpp"
#include "config/validate.hpp"
#include "slam_system/parameters.hpp"

namespace df::slam {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Reflection;

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
    const google::protobuf::Descriptor* d = params.GetDescriptor();
    const Reflection* r = params.GetReflection();
    Status status = Status::ok();
    slam::for_each_section(config, [&](const char* name, auto& section) {
        if (!status) return;
        const FieldDescriptor* f = d->FindFieldByName(name);
        if (f == nullptr) {
            status = error(StatusCode::kInvalidArgument,
                           std::string("slam.proto has no section ") + name);
        } else if (r->HasField(params, f)) {
            status = config::apply_params(r->GetMessage(params, f), &section)
                         .with_context(std::string("slam.") + name);
        }
    });
    return status;
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
