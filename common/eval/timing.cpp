#include "eval/timing.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "eval/stats.hpp"

namespace df::eval {

namespace {

bool valid_name(const std::string& name) {
    if (name.empty()) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
        if (!ok) return false;
    }
    return true;
}

bool split_pair(const std::string& token, std::string* key, std::string* value) {
    const size_t eq = token.find('=');
    if (eq == std::string::npos) return false;
    *key = token.substr(0, eq);
    *value = token.substr(eq + 1);
    return true;
}

}  // namespace

std::string format_timing_line(int64_t seq, const std::string& stage,
                               const std::vector<std::pair<std::string, double>>& steps_ms) {
    std::string line = "timing seq=" + std::to_string(seq) + " stage=" + stage;
    for (const auto& [name, ms] : steps_ms) {
        char value[64];
        std::snprintf(value, sizeof value, "%.3f", ms);
        line += " " + name + "=" + value;
    }
    return line;
}

Result<std::optional<TimingSample>> parse_timing_line(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string t; in >> t;) tokens.push_back(t);
    size_t start = tokens.size();
    for (size_t i = 0; i + 1 < tokens.size(); ++i) {
        if (tokens[i] == "timing" && tokens[i + 1].rfind("seq=", 0) == 0) {
            start = i + 1;
            break;
        }
    }
    if (start == tokens.size()) return std::optional<TimingSample>();
    TimingSample sample;
    const std::string seq = tokens[start].substr(4);
    char* end = nullptr;
    errno = 0;
    const long long seq_value = std::strtoll(seq.c_str(), &end, 10);
    if (seq.empty() || end != seq.c_str() + seq.size() || errno == ERANGE) {
        return error(StatusCode::kInvalidArgument,
                     "timing record: expected an integer after 'seq=', found '" + seq + "'");
    }
    sample.seq = seq_value;
    std::string key, value;
    if (start + 1 >= tokens.size() || !split_pair(tokens[start + 1], &key, &value) ||
        key != "stage" || !valid_name(value)) {
        return error(StatusCode::kInvalidArgument,
                     "timing record: expected 'stage=<name>' after seq=" + seq);
    }
    sample.stage = value;
    for (size_t i = start + 2; i < tokens.size(); ++i) {
        if (!split_pair(tokens[i], &key, &value) || !valid_name(key) || key == "seq" ||
            key == "stage") {
            return error(
                StatusCode::kInvalidArgument,
                "timing record: expected '<step>=<milliseconds>', found '" + tokens[i] + "'");
        }
        errno = 0;
        const double ms = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(ms) || ms < 0) {
            return error(StatusCode::kInvalidArgument,
                         "timing record: step '" + key +
                             "' needs a non-negative number of milliseconds, found '" + value +
                             "'");
        }
        sample.steps_ms.emplace_back(key, ms);
    }
    if (sample.steps_ms.empty()) {
        return error(StatusCode::kInvalidArgument,
                     "timing record: no '<step>=<milliseconds>' after stage=" + sample.stage);
    }
    return std::optional<TimingSample>(std::move(sample));
}

Result<TimingLog> read_timing_log(const std::string& file) {
    std::ifstream in(file);
    if (!in) return error(StatusCode::kNotFound, file + ": cannot open log file");
    TimingLog log;
    std::string line;
    while (std::getline(in, line)) {
        ++log.lines;
        auto parsed = parse_timing_line(line);
        if (!parsed) {
            log.errors.push_back(file + ":" + std::to_string(log.lines) + ": " +
                                 parsed.status().message());
        } else if (parsed->has_value()) {
            log.samples.push_back(std::move(**parsed));
        }
    }
    if (in.bad()) return error(StatusCode::kIoError, file + ": cannot read log file");
    return log;
}

std::vector<TimingStats> summarize_timing(const std::vector<TimingSample>& samples) {
    std::map<std::string, std::vector<std::string>> step_order;  // per stage
    std::map<std::pair<std::string, std::string>, std::vector<double>> values;
    for (const TimingSample& s : samples) {
        for (const auto& [step, ms] : s.steps_ms) {
            auto& list = values[{s.stage, step}];
            if (list.empty()) step_order[s.stage].push_back(step);
            list.push_back(ms);
        }
    }
    std::vector<TimingStats> stats;
    for (const auto& [stage, steps] : step_order) {
        for (const std::string& step : steps) {
            const std::vector<double>& v = values[{stage, step}];
            const ErrorStats e = summarize_errors(v);
            TimingStats t;
            t.stage = stage;
            t.step = step;
            t.count = e.count;
            t.mean_ms = e.mean;
            t.median_ms = e.median;
            t.p95_ms = percentile(v, 95);
            t.max_ms = e.max;
            stats.push_back(t);
        }
    }
    return stats;
}

}  // namespace df::eval
