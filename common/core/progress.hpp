#pragma once
/// Progress of long work (frames of a run, of a generated sequence): on a terminal one line
/// rewritten in place at most four times a second ("slam 120/900 frames  14.2/s  0:55 left");
/// in a log or CI (stderr not a terminal) one log line every `every` items and one at the end.
#include <chrono>
#include <cstdint>
#include <string>

namespace df {

class Progress {
  public:
    /// `label`: what is counted ("frames"); total: items in all, or -1 when unknown (a live
    /// camera). DF_PROGRESS=0 in the environment turns the terminal line off (log lines stay).
    Progress(std::string label, int64_t total, int64_t every = 100);
    ~Progress() { finish(); }
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// `done` items are done.
    void update(int64_t done);
    /// The total, once it is known.
    void set_total(int64_t total) { total_ = total; }
    /// Ends the terminal line (called by the destructor too).
    void finish();

    /// "120/900 frames  14.2/s  0:55 left" for `done` items after `seconds`.
    static std::string text(const std::string& label, int64_t done, int64_t total, double seconds);

  private:
    std::string label_;
    int64_t total_, every_;
    bool terminal_;
    int64_t done_ = 0, last_logged_ = 0;
    bool finished_ = false;
    std::chrono::steady_clock::time_point start_, last_drawn_;
};

}  // namespace df
