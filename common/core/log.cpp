#include "core/log.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <mutex>
#include <string>

namespace df::log {
namespace {

struct State {
    std::mutex mutex;
    Level level = Level::kInfo;
    std::string component = "df";
    std::string status_line;  ///< the progress line shown on the terminal, "" none
    State() {
        if (const char* env = std::getenv("DF_LOG_LEVEL")) {
            std::string v(env);
            if (v == "debug")
                level = Level::kDebug;
            else if (v == "warn")
                level = Level::kWarn;
            else if (v == "error")
                level = Level::kError;
        }
    }
};

State& state() {
    static State s;  // process-wide logger state; the one deliberate static
    return s;
}

const char* name(Level l) {
    switch (l) {
        case Level::kDebug:
            return "debug";
        case Level::kInfo:
            return "info";
        case Level::kWarn:
            return "warn";
        case Level::kError:
            return "error";
    }
    return "?";
}

}  // namespace

void set_level(Level l) { state().level = l; }
Level level() { return state().level; }
void set_component(const std::string& n) {
    std::lock_guard<std::mutex> lock(state().mutex);
    state().component = n;
}

void write(Level l, const std::string& message) {
    using namespace std::chrono;
    const auto now = system_clock::now();
    const std::time_t t = system_clock::to_time_t(now);
    const int ms =
        static_cast<int>(duration_cast<milliseconds>(now.time_since_epoch()).count() % 1000);
    std::tm tm{};
    localtime_r(&t, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &tm);
    std::lock_guard<std::mutex> lock(state().mutex);
    // A log line goes above the progress line, which is drawn again below it.
    if (!state().status_line.empty()) std::fputs("\r\033[K", stderr);
    std::fprintf(stderr, "%s.%03d [%s] %s: %s\n", stamp, ms, name(l), state().component.c_str(),
                 message.c_str());
    if (!state().status_line.empty()) std::fputs(state().status_line.c_str(), stderr);
    std::fflush(stderr);
}

void status_line(const std::string& text) {
    std::lock_guard<std::mutex> lock(state().mutex);
    state().status_line = text;
    std::fprintf(stderr, "\r%s\033[K", text.c_str());
    std::fflush(stderr);
}

void end_status_line() {
    std::lock_guard<std::mutex> lock(state().mutex);
    if (state().status_line.empty()) return;
    state().status_line.clear();
    std::fputs("\n", stderr);
    std::fflush(stderr);
}

}  // namespace df::log
