#include "core/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/log.hpp"

namespace df {
namespace {

bool stderr_is_terminal() {
    const char* env = std::getenv("DF_PROGRESS");
    if (env != nullptr && std::strcmp(env, "0") == 0) return false;
    return isatty(STDERR_FILENO) == 1;
}

std::string duration(double s) {
    const long total = std::lround(std::max(0.0, s));
    char text[32];
    if (total >= 3600) {
        std::snprintf(text, sizeof(text), "%ld:%02ld:%02ld", total / 3600, total / 60 % 60,
                      total % 60);
    } else {
        std::snprintf(text, sizeof(text), "%ld:%02ld", total / 60, total % 60);
    }
    return text;
}

}  // namespace

Progress::Progress(std::string label, int64_t total, int64_t every)
    : label_(std::move(label)),
      total_(total),
      every_(every > 0 ? every : 100),
      terminal_(stderr_is_terminal()),
      start_(std::chrono::steady_clock::now()),
      last_drawn_(start_) {}

std::string Progress::text(const std::string& label, int64_t done, int64_t total, double seconds) {
    const double rate = seconds > 0 ? static_cast<double>(done) / seconds : 0.0;
    char line[160];
    if (total > 0) {
        const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
        std::snprintf(line, sizeof(line), "%lld/%lld %s (%.0f %%)  %.1f/s  %s left",
                      static_cast<long long>(done), static_cast<long long>(total), label.c_str(),
                      100.0 * static_cast<double>(done) / static_cast<double>(total), rate,
                      duration(left).c_str());
    } else {
        std::snprintf(line, sizeof(line), "%lld %s  %.1f/s  %s", static_cast<long long>(done),
                      label.c_str(), rate, duration(seconds).c_str());
    }
    return line;
}

void Progress::update(int64_t done) {
    done_ = done;
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - start_).count();
    if (terminal_) {
        if (now - last_drawn_ < std::chrono::milliseconds(250) && done != total_) return;
        last_drawn_ = now;
        log::status_line(text(label_, done, total_, seconds));
        return;
    }
    if (done - last_logged_ >= every_) {
        last_logged_ = done;
        log::info(text(label_, done, total_, seconds));
    }
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (terminal_) {
        log::status_line(text(label_, done_, total_, seconds));
        log::end_status_line();
    } else if (done_ != last_logged_) {
        log::info(text(label_, done_, total_, seconds));
    }
}

}  // namespace df
