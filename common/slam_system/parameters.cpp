#include "slam_system/parameters.hpp"

#include <charconv>
#include <cstdlib>
#include <sstream>

namespace df::slam {
namespace {

template <typename T>
bool parse_number(const std::string& text, T* out) {
    if (text.empty()) return false;
    char* end = nullptr;
    if constexpr (std::is_same_v<T, float>) {
        *out = std::strtof(text.c_str(), &end);
    } else if constexpr (std::is_same_v<T, double>) {
        *out = std::strtod(text.c_str(), &end);
    } else if constexpr (std::is_same_v<T, int>) {
        const long v = std::strtol(text.c_str(), &end, 10);
        if (v < -2147483647L || v > 2147483647L) return false;
        *out = static_cast<int>(v);
    } else {
        if (text[0] == '-') return false;
        *out = static_cast<T>(std::strtoull(text.c_str(), &end, 10));
    }
    return end != nullptr && *end == '\0';
}

template <typename T>
bool parse_list(const std::string& text, std::vector<T>* out) {
    std::vector<T> values;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        T v{};
        if (!parse_number(item, &v)) return false;
        values.push_back(v);
    }
    if (values.empty()) return false;
    *out = std::move(values);
    return true;
}

template <typename T>
std::string number_text(T v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

/// Appends every field of a generated parameter struct (nested structs walked) as
/// "<prefix><field>".
template <class S>
void add_fields(const std::string& prefix, S& s, std::vector<Parameter>* out) {
    s.for_each_field([&](const params::FieldInfo& info, auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (params::detail::is_struct<T>::value) {
            add_fields(prefix + info.name + ".", value, out);
        } else {
            out->push_back({prefix + info.name, info.doc, &value});
        }
    });
}

}  // namespace

std::vector<Parameter> parameters(SystemConfig* c) {
    // The fields come from the generated structs (declared once, in slam.proto).
    std::vector<Parameter> out;
    for_each_section(c, [&out](const char* name, auto& section) {
        add_fields(std::string(name) + ".", section, &out);
    });
    return out;
}

std::string value_text(const Parameter& parameter) {
    return std::visit(
        [](auto* v) -> std::string {
            using T = std::remove_pointer_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                return *v ? "true" : "false";
            } else if constexpr (std::is_same_v<T, std::vector<int>> ||
                                 std::is_same_v<T, std::vector<float>>) {
                std::string text;
                for (size_t i = 0; i < v->size(); ++i)
                    text += (i ? "," : "") + number_text((*v)[i]);
                return text;
            } else {
                return number_text(*v);
            }
        },
        parameter.value);
}

Status set_value(const Parameter& parameter, const std::string& text) {
    const bool ok = std::visit(
        [&](auto* v) -> bool {
            using T = std::remove_pointer_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                if (text == "true" || text == "1") return *v = true, true;
                if (text == "false" || text == "0") return *v = false, true;
                return false;
            } else if constexpr (std::is_same_v<T, std::vector<int>> ||
                                 std::is_same_v<T, std::vector<float>>) {
                return parse_list(text, v);
            } else {
                T parsed{};
                if (!parse_number(text, &parsed)) return false;
                *v = parsed;
                return true;
            }
        },
        parameter.value);
    if (ok) return Status::ok();
    return error(StatusCode::kInvalidArgument,
                 "parameter " + parameter.name + ": cannot read '" + text + "' as its value");
}

std::string describe(const SystemConfig& config) {
    SystemConfig copy = config;
    std::string text;
    for (const Parameter& p : parameters(&copy)) {
        text += p.name + " = " + value_text(p) + "\n";
    }
    return text;
}

}  // namespace df::slam
