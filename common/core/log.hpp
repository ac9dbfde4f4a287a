#pragma once
/// The project's one logger: lines to stderr as
///   2026-11-24T10:00:00.123 [level] component: message
/// Per-frame lines carry the frame sequence number ("seq=N").
#include <sstream>
#include <string>

namespace df::log {

enum class Level { kDebug = 0, kInfo, kWarn, kError };

/// Sets the lowest level printed (default info; env DF_LOG_LEVEL=debug|info|warn|error).
void set_level(Level level);
Level level();
/// Sets the component name printed on every line of this process (e.g. "capture").
void set_component(const std::string& name);
void write(Level level, const std::string& message);
/// Shows `text` as the terminal's progress line (rewritten in place; log lines print above it).
/// Only for a terminal: see core/progress.hpp.
void status_line(const std::string& text);
/// Ends the progress line (a newline), if one is shown.
void end_status_line();

namespace detail {
template <typename... Args>
std::string join(const Args&... args) {
    std::ostringstream s;
    (s << ... << args);
    return s.str();
}
}  // namespace detail

template <typename... Args>
void debug(const Args&... a) {
    if (level() <= Level::kDebug) write(Level::kDebug, detail::join(a...));
}
template <typename... Args>
void info(const Args&... a) {
    if (level() <= Level::kInfo) write(Level::kInfo, detail::join(a...));
}
template <typename... Args>
void warn(const Args&... a) {
    if (level() <= Level::kWarn) write(Level::kWarn, detail::join(a...));
}
template <typename... Args>
void error(const Args&... a) {
    write(Level::kError, detail::join(a...));
}

}  // namespace df::log
