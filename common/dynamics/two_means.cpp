#include "dynamics/two_means.hpp"

#include <algorithm>
#include <cmath>

namespace df::dynamics {

Histogram::Histogram(float max_value, int bins)
    : max_value_(max_value > 0.f ? max_value : 1.f),
      bin_width_(max_value_ / static_cast<float>(std::max(bins, 2))),
      bins_(static_cast<size_t>(std::max(bins, 2)), 0) {}

void Histogram::add(const Histogram& other) {
    const size_t n = std::min(bins_.size(), other.bins_.size());
    for (size_t b = 0; b < n; ++b) bins_[b] += other.bins_[b];
    count_ += other.count_;
}

float Histogram::quantile(float q) const {
    if (count_ == 0) return 0.f;
    const double need = std::clamp(static_cast<double>(q), 0.0, 1.0) * count_;
    double below = 0;
    for (size_t b = 0; b < bins_.size(); ++b) {
        below += bins_[b];
        if (below >= need && below > 0) return bin_width_ * static_cast<float>(b + 1);
    }
    return max_value_;
}

TwoMeans Histogram::two_means(int max_iterations) const {
    TwoMeans out;
    const int n = static_cast<int>(bins_.size());
    int first = -1, last = -1;
    for (int b = 0; b < n; ++b) {
        if (bins_[static_cast<size_t>(b)] == 0) continue;
        if (first < 0) first = b;
        last = b;
    }
    const auto centre = [this](int b) { return (static_cast<float>(b) + 0.5f) * bin_width_; };
    if (first < 0) return out;
    if (first == last) {
        out.low = out.high = out.threshold = centre(first);
        out.low_count = count_;
        return out;
    }
    double low = centre(first), high = centre(last);
    int split = -1;  // bins <= split are low
    for (int it = 0; it < max_iterations; ++it) {
        const double t = 0.5 * (low + high);
        const int new_split =
            std::clamp(static_cast<int>(std::floor(t / bin_width_ - 0.5)), first, last - 1);
        ++out.iterations;
        if (new_split == split) break;
        split = new_split;
        double sum_low = 0, sum_high = 0;
        long n_low = 0, n_high = 0;
        for (int b = first; b <= last; ++b) {
            const int c = bins_[static_cast<size_t>(b)];
            (b <= split ? sum_low : sum_high) += static_cast<double>(c) * centre(b);
            (b <= split ? n_low : n_high) += c;
        }
        if (n_low > 0) low = sum_low / static_cast<double>(n_low);
        if (n_high > 0) high = sum_high / static_cast<double>(n_high);
        out.low_count = static_cast<int>(n_low);
        out.high_count = static_cast<int>(n_high);
    }
    out.low = static_cast<float>(low);
    out.high = static_cast<float>(high);
    // The boundary between the clusters: the upper edge of the last low bin.
    out.threshold = static_cast<float>(split + 1) * bin_width_;
    return out;
}

TwoMeans two_means(const std::vector<float>& values, float max_value, int bins) {
    Histogram h(max_value, bins);
    for (float v : values) h.add(v);
    return h.two_means();
}

}  // namespace df::dynamics
