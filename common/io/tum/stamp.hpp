#pragma once
/// Exact time stamps of TUM text files (rgb.txt, depth.txt, associations.txt, groundtruth.txt),
/// read from their decimal text into integer nanoseconds with no floating point on the way.
///
/// Rules (docs/hardening.md, "Input and options"):
///  - Seconds: decimal digits with an optional '.' and at most 9 fractional digits
///    ("1305031102.175304" is 1305031102175304000 ns exactly). More than 9 fractional digits,
///    a sign, an exponent ("1e9"), "nan", "inf" or any other character is refused.
///  - Nanoseconds: an integer stamp (no '.') of 19 digits or more is read as nanoseconds, as
///    recorders write them (every ns stamp from 2001-09-09 to 2262 has 19 digits).
///  - Range: 0 .. 9223372036.854775807 s (int64 nanoseconds, year 2262); beyond it is refused.
///  - One unit per file: the first stamp of a file fixes its unit; a stamp of the other unit on
///    a later line is refused (StampReader).
#include <cstdint>
#include <string>

#include "core/status.hpp"

namespace df::io {

enum class StampUnit { kSeconds, kNanoseconds };

struct ParsedStamp {
    int64_t ns = 0;
    StampUnit unit = StampUnit::kSeconds;
};

/// Parses one stamp field by the rules above. kInvalidArgument with a message saying what was
/// found and what is allowed (without file and line: callers add them).
Result<ParsedStamp> parse_stamp(const std::string& field);

/// Reads the stamps of one file, keeping its unit consistent (the first stamp fixes it).
class StampReader {
  public:
    /// Parses `field` of line `line`; an error names the line of the stamp that fixed the unit
    /// when the units differ.
    Result<int64_t> read(const std::string& field, int line);

  private:
    bool has_unit_ = false;
    StampUnit unit_ = StampUnit::kSeconds;
    int unit_line_ = 0;
};

/// A stamp in seconds with `decimals` fractional digits (0..9), rounded half up, computed in
/// integers: stamp_text(1305031102175304000) == "1305031102.175304". The one function from a
/// stamp to a file name ("<stamp_text>.png"). stamp_ns must be >= 0.
std::string stamp_text(int64_t stamp_ns, int decimals = 6);

/// A window in seconds (max_difference_s) as nanoseconds; kInvalidArgument naming `what` unless
/// finite and in (0, 1e6] s.
Result<int64_t> window_ns(double seconds, const std::string& what);

}  // namespace df::io
