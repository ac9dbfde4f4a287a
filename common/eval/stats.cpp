#include "eval/stats.hpp"

#include <algorithm>
#include <cmath>

namespace df::eval {

ErrorStats summarize_errors(const std::vector<double>& values) {
    ErrorStats s;
    s.count = values.size();
    if (values.empty()) return s;
    double sum = 0, sum_sq = 0;
    for (double v : values) {
        sum += v;
        sum_sq += v * v;
    }
    const double n = static_cast<double>(values.size());
    s.mean = sum / n;
    s.rmse = std::sqrt(sum_sq / n);
    double dev_sq = 0;  // two passes: no cancellation for large means
    for (double v : values) dev_sq += (v - s.mean) * (v - s.mean);
    s.stddev = std::sqrt(dev_sq / n);
    std::vector<double> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    s.min = sorted.front();
    s.max = sorted.back();
    const size_t mid = sorted.size() / 2;
    s.median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
    return s;
}

double percentile(std::vector<double> values, double q) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    const double rank = std::clamp(q, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(rank));
    const size_t hi = std::min(lo + 1, values.size() - 1);
    const double frac = rank - static_cast<double>(lo);
    return values[lo] + frac * (values[hi] - values[lo]);
}

}  // namespace df::eval
