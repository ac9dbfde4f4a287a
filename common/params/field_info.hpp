#pragma once
/// What the generated parameter structs (params/slam_params.hpp, generated at build time from
/// common/config/slam.proto by df_gen_params) say about each of their fields, and the checks
/// derived from it. No protobuf here: the algorithm libraries use these structs as their
/// configuration without linking protobuf.
#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

namespace df::params {

/// One field of a generated struct, as its .proto declares it.
struct FieldInfo {
    const char* name;     ///< field name ("icp_max_distance_m")
    const char* unit;     ///< (unit), "" when none
    const char* doc;      ///< (doc): the meaning in one line
    const char* allowed;  ///< what one value may be ("> 0 and <= 1", "finite", "")
    bool has_min;
    double min;
    bool min_exclusive;
    bool has_max;
    double max;
    bool max_exclusive;
    bool non_empty;  ///< a string (each string of a list) must not be empty
};

namespace detail {

struct AnyField {
    template <class T>
    void operator()(const FieldInfo&, T&) const {}
};

/// Whether T is a generated parameter struct (it has for_each_field).
template <class T, class = void>
struct is_struct : std::false_type {};
template <class T>
struct is_struct<T, std::void_t<decltype(std::declval<T&>().for_each_field(AnyField{}))>>
    : std::true_type {};

template <class T>
std::string text_of(T v) {
    char text[64];
    if constexpr (std::is_floating_point_v<T>) {
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
    } else if constexpr (std::is_signed_v<T>) {
        std::snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
    } else {
        std::snprintf(text, sizeof text, "%llu", static_cast<unsigned long long>(v));
    }
    return text;
}

/// "" when `v` is allowed by `info`, else "<path> is <v>, allowed: <rule>".
template <class T>
std::string check_value(const FieldInfo& info, const std::string& path, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
        return "";
    } else if constexpr (std::is_same_v<T, std::string>) {
        return info.non_empty && v.empty() ? path + " is empty, allowed: " + info.allowed : "";
    } else {
        bool ok = true;
        if constexpr (std::is_floating_point_v<T>) ok = std::isfinite(v);
        const long double x = static_cast<long double>(v);
        if (ok && info.has_min) ok = info.min_exclusive ? x > info.min : x >= info.min;
        if (ok && info.has_max) ok = info.max_exclusive ? x < info.max : x <= info.max;
        if (ok) return "";
        std::string unit = *info.unit ? std::string(" [") + info.unit + "]" : "";
        return path + " is " + text_of(v) + ", allowed: " + info.allowed + unit;
    }
}

}  // namespace detail

/// Every field of a generated struct (nested structs and each element of a list included)
/// against the range its .proto declares, and every float finite. "" when all are allowed,
/// else the first offence: "<prefix><field> is <value>, allowed: <rule> [unit]", e.g.
/// "map.confidence_sigma is 0, allowed: > 0 and <= 100".
template <class S>
std::string check(const S& s, const std::string& prefix = "") {
    std::string bad;
    s.for_each_field([&](const FieldInfo& info, const auto& value) {
        if (!bad.empty()) return;
        using T = std::decay_t<decltype(value)>;
        const std::string path = prefix + info.name;
        if constexpr (detail::is_struct<T>::value) {
            bad = check(value, path + ".");
        } else if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, std::string>) {
            bad = detail::check_value(info, path, value);
        } else {
            for (size_t i = 0; i < value.size() && bad.empty(); ++i)
                bad = detail::check_value(info, path + "[" + std::to_string(i) + "]", value[i]);
        }
    });
    return bad;
}

}  // namespace df::params
