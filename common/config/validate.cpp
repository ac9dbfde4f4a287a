#include "config/validate.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <google/protobuf/text_format.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "options.pb.h"

namespace df::config {

namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

std::string number_text(double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
}

bool is_number(const FieldDescriptor* f) {
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_INT32:
        case FieldDescriptor::CPPTYPE_INT64:
        case FieldDescriptor::CPPTYPE_UINT32:
        case FieldDescriptor::CPPTYPE_UINT64:
        case FieldDescriptor::CPPTYPE_FLOAT:
        case FieldDescriptor::CPPTYPE_DOUBLE:
            return true;
        default:
            return false;
    }
}

bool is_float(const FieldDescriptor* f) {
    return f->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT ||
           f->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE;
}

/// The value of a numeric field (element `index` of a repeated one) as long double, exact for
/// every integer type.
long double number_value(const Message& m, const FieldDescriptor* f, int index) {
    const Reflection* r = m.GetReflection();
    const bool rep = f->is_repeated();
    switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_INT32:
            return rep ? r->GetRepeatedInt32(m, f, index) : r->GetInt32(m, f);
        case FieldDescriptor::CPPTYPE_INT64:
            return rep ? r->GetRepeatedInt64(m, f, index) : r->GetInt64(m, f);
        case FieldDescriptor::CPPTYPE_UINT32:
            return rep ? r->GetRepeatedUInt32(m, f, index) : r->GetUInt32(m, f);
        case FieldDescriptor::CPPTYPE_UINT64:
            return rep ? r->GetRepeatedUInt64(m, f, index) : r->GetUInt64(m, f);
        case FieldDescriptor::CPPTYPE_FLOAT:
            return rep ? r->GetRepeatedFloat(m, f, index) : r->GetFloat(m, f);
        case FieldDescriptor::CPPTYPE_DOUBLE:
            return rep ? r->GetRepeatedDouble(m, f, index) : r->GetDouble(m, f);
        default:
            return 0;
    }
}

std::string value_text(const Message& m, const FieldDescriptor* f, int index) {
    std::string text;
    google::protobuf::TextFormat::PrintFieldValueToString(m, f, f->is_repeated() ? index : -1,
                                                          &text);
    return text;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool in_choices(const std::string& value, const std::string& choices) {
    std::stringstream list(choices);
    std::string choice;
    while (std::getline(list, choice, '|')) {
        if (lower(choice) == lower(value)) return true;
    }
    return false;
}

bool in_range(long double v, const Range& range) {
    if (range.has_min() && (range.min_exclusive() ? !(v > range.min()) : !(v >= range.min())))
        return false;
    if (range.has_max() && (range.max_exclusive() ? !(v < range.max()) : !(v <= range.max())))
        return false;
    return true;
}

Status refuse(const std::string& path, const std::string& found, const FieldDescriptor* f) {
    std::string message = path + " is " + found + ", allowed: " + rule_text(f);
    const std::string unit = unit_of(f);
    if (!unit.empty()) message += " (unit: " + unit + ")";
    return error(StatusCode::kInvalidArgument, message);
}

Status check_value(const Message& m, const FieldDescriptor* f, int index, const std::string& path) {
    const auto& options = f->options();
    if (is_number(f)) {
        const long double v = number_value(m, f, index);
        if (is_float(f) && !std::isfinite(v)) return refuse(path, value_text(m, f, index), f);
        if (options.HasExtension(range) && !in_range(v, options.GetExtension(range))) {
            return refuse(path, value_text(m, f, index), f);
        }
        return Status::ok();
    }
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_STRING) {
        const Reflection* r = m.GetReflection();
        const std::string v =
            f->is_repeated() ? r->GetRepeatedString(m, f, index) : r->GetString(m, f);
        if (options.GetExtension(non_empty) && v.empty()) return refuse(path, "empty", f);
        if (options.HasExtension(choices) && !in_choices(v, options.GetExtension(choices))) {
            return refuse(path, value_text(m, f, index), f);
        }
    }
    return Status::ok();
}

/// "class_score_thresholds[person]" for a map entry with a string key, else "name[i]".
std::string element_path(const std::string& path, const Message& m, const FieldDescriptor* f,
                         int index) {
    if (f->is_map()) {
        const Message& entry = m.GetReflection()->GetRepeatedMessage(m, f, index);
        const FieldDescriptor* key = entry.GetDescriptor()->FindFieldByNumber(1);
        if (key != nullptr && key->cpp_type() == FieldDescriptor::CPPTYPE_STRING) {
            return path + "[" + entry.GetReflection()->GetString(entry, key) + "]";
        }
    }
    return path + "[" + std::to_string(index) + "]";
}

void help_into(const Message& prototype, const std::string& prefix, int depth,
               std::ostringstream& out) {
    const Descriptor* type = prototype.GetDescriptor();
    const Reflection* r = prototype.GetReflection();
    for (int i = 0; i < type->field_count(); ++i) {
        const FieldDescriptor* f = type->field(i);
        const std::string path = prefix + f->name();
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE && !f->is_repeated()) {
            if (depth < 8) help_into(r->GetMessage(prototype, f), path + ".", depth + 1, out);
            continue;
        }
        std::string value = "[]";
        if (!f->is_repeated()) {
            value = value_text(prototype, f, -1);
            if (!f->has_default_value() && is_number(f)) value = "(unset)";
        }
        std::string allowed = allowed_text(f);
        const std::string unit = unit_of(f);
        if (!unit.empty()) allowed += (allowed.empty() ? "" : " ") + ("[" + unit + "]");
        char line[512];
        std::snprintf(line, sizeof line, "  %-44s %-12s %s\n", path.c_str(), value.c_str(),
                      allowed.c_str());
        out << line;
    }
}

}  // namespace

std::string unit_of(const FieldDescriptor* f) {
    return f->options().HasExtension(unit) ? f->options().GetExtension(unit) : "";
}

std::string allowed_text(const FieldDescriptor* f) {
    const std::string text = rule_text(f);
    return f->is_repeated() && !text.empty() ? "each " + text : text;
}

std::string rule_text(const FieldDescriptor* f) {
    const auto& options = f->options();
    std::string text;
    if (options.HasExtension(range)) {
        const Range& r = options.GetExtension(range);
        if (r.has_min()) text += (r.min_exclusive() ? "> " : ">= ") + number_text(r.min());
        if (r.has_max()) {
            text += (text.empty() ? "" : " and ") + std::string(r.max_exclusive() ? "< " : "<= ") +
                    number_text(r.max());
        }
    } else if (is_float(f)) {
        text = "finite";
    }
    if (options.HasExtension(choices)) text = "one of " + options.GetExtension(choices);
    if (options.GetExtension(non_empty))
        text += (text.empty() ? "" : ", ") + std::string("not empty");
    return text;
}

Status check_fields(const Message& message, const std::string& prefix) {
    const Reflection* r = message.GetReflection();
    std::vector<const FieldDescriptor*> fields;
    r->ListFields(message, &fields);
    for (const FieldDescriptor* f : fields) {
        const std::string path = prefix + f->name();
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
            if (!f->is_repeated()) {
                DF_RETURN_IF_ERROR(check_fields(r->GetMessage(message, f), path + "."));
                continue;
            }
            for (int i = 0; i < r->FieldSize(message, f); ++i) {
                DF_RETURN_IF_ERROR(check_fields(r->GetRepeatedMessage(message, f, i),
                                                element_path(path, message, f, i) + "."));
            }
            continue;
        }
        if (!f->is_repeated()) {
            DF_RETURN_IF_ERROR(check_value(message, f, -1, path));
            continue;
        }
        for (int i = 0; i < r->FieldSize(message, f); ++i) {
            DF_RETURN_IF_ERROR(check_value(message, f, i, path + "[" + std::to_string(i) + "]"));
        }
    }
    return Status::ok();
}

Status check(const Message& message) {
    DF_RETURN_IF_ERROR(check_fields(message));
    return check_rules(message);
}

std::string options_help(const Descriptor* type) {
    const Message* prototype =
        google::protobuf::MessageFactory::generated_factory()->GetPrototype(type);
    std::ostringstream out;
    out << "Options (--set 'field: value', or in the --config file), default and allowed values:\n";
    if (prototype != nullptr) help_into(*prototype, "", 0, out);
    return out.str();
}

}  // namespace df::config
