#include "io/tum/stamp.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace df::io {
namespace {

constexpr int64_t kNsPerS = 1000000000;
constexpr int64_t kMaxNs = std::numeric_limits<int64_t>::max();
constexpr int kNsDigits = 19;  ///< integer stamps with at least this many digits are ns

std::string quoted(const std::string& field) {
    constexpr size_t kMax = 40;
    return "'" + (field.size() <= kMax ? field : field.substr(0, kMax) + "...") + "'";
}

Status refuse(const std::string& field, const std::string& why) {
    return error(StatusCode::kInvalidArgument,
                 "time stamp " + quoted(field) + " " + why +
                     " (expected seconds as a decimal number with at most 9 decimals, or "
                     "integer nanoseconds of 19 digits, from 0 to 9223372036.854775807 s)");
}

/// value * 10 + digit without overflow; false if it would pass kMaxNs.
bool push_digit(int64_t* value, char digit) {
    const int d = digit - '0';
    if (*value > (kMaxNs - d) / 10) return false;
    *value = *value * 10 + d;
    return true;
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

Result<ParsedStamp> parse_stamp(const std::string& field) {
    if (field.empty()) return refuse(field, "is empty");
    if (field[0] == '-') return refuse(field, "is negative");
    const size_t dot = field.find('.');
    const std::string whole = field.substr(0, dot);
    const std::string fraction = dot == std::string::npos ? "" : field.substr(dot + 1);
    for (const std::string* part : {&whole, &fraction}) {
        for (char c : *part) {
            if (!is_digit(c)) return refuse(field, "is not a decimal number");
        }
    }
    if (whole.empty() && fraction.empty()) return refuse(field, "has no digits");
    if (fraction.size() > 9) {
        return refuse(field, "has " + std::to_string(fraction.size()) +
                                 " decimals, more than nanoseconds resolve");
    }

    ParsedStamp out;
    size_t significant = whole.find_first_not_of('0');
    significant = significant == std::string::npos ? 0 : whole.size() - significant;
    if (dot == std::string::npos && significant >= kNsDigits) {
        int64_t ns = 0;
        for (char c : whole) {
            if (!push_digit(&ns, c)) return refuse(field, "is beyond year 2262 in nanoseconds");
        }
        out.ns = ns;
        out.unit = StampUnit::kNanoseconds;
        return out;
    }
    int64_t seconds = 0;
    for (char c : whole) {
        if (!push_digit(&seconds, c) || seconds > kMaxNs / kNsPerS) {
            return refuse(field, "is beyond year 2262 in seconds");
        }
    }
    int64_t sub = 0;
    for (size_t i = 0; i < 9; ++i) sub = sub * 10 + (i < fraction.size() ? fraction[i] - '0' : 0);
    if (seconds * kNsPerS > kMaxNs - sub) return refuse(field, "is beyond year 2262 in seconds");
    out.ns = seconds * kNsPerS + sub;
    return out;
}

Result<int64_t> StampReader::read(const std::string& field, int line) {
    auto stamp = parse_stamp(field);
    if (!stamp) return stamp.status();
    if (!has_unit_) {
        has_unit_ = true;
        unit_ = stamp->unit;
        unit_line_ = line;
    } else if (stamp->unit != unit_) {
        const char* name = unit_ == StampUnit::kNanoseconds ? "nanoseconds" : "seconds";
        const char* other = unit_ == StampUnit::kNanoseconds ? "seconds" : "nanoseconds";
        return error(StatusCode::kInvalidArgument, "time stamp '" + field + "' is in " + other +
                                                       " but the file's first stamp (line " +
                                                       std::to_string(unit_line_) + ") is in " +
                                                       name + "; a file keeps one unit");
    }
    return stamp->ns;
}

std::string stamp_text(int64_t stamp_ns, int decimals) {
    if (decimals < 0) decimals = 0;
    if (decimals > 9) decimals = 9;
    int64_t unit = 1;
    for (int i = decimals; i < 9; ++i) unit *= 10;
    // Rounded half up in units of 10^-decimals s; no overflow: unit / 2 <= 5e8 and the quotient
    // is taken first.
    int64_t units = stamp_ns / unit + (stamp_ns % unit >= (unit + 1) / 2 && unit > 1 ? 1 : 0);
    int64_t per_second = kNsPerS / unit;
    char buffer[48];
    if (decimals == 0) {
        std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(units));
    } else {
        std::snprintf(buffer, sizeof buffer, "%lld.%0*lld",
                      static_cast<long long>(units / per_second), decimals,
                      static_cast<long long>(units % per_second));
    }
    return buffer;
}

Result<int64_t> window_ns(double seconds, const std::string& what) {
    if (!std::isfinite(seconds) || !(seconds > 0) || seconds > 1e6) {
        char text[64];
        std::snprintf(text, sizeof text, "%g", seconds);
        return error(StatusCode::kInvalidArgument,
                     what + " is " + text + " s, allowed: > 0 and <= 1e6 s, finite");
    }
    return static_cast<int64_t>(std::llround(seconds * 1e9));
}

}  // namespace df::io
