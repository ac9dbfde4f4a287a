#pragma once
/// 2-means of non-negative scalars (DetectFusion's split of ICP residuals into a static and a
/// dynamic cluster): Lloyd's iterations on a histogram, so the cost is one pass over the values
/// plus a few passes over the bins, whatever their number. DDS-free.
#include <algorithm>
#include <vector>

namespace df::dynamics {

struct TwoMeans {
    float low = 0.f;        ///< centroid of the lower cluster
    float high = 0.f;       ///< centroid of the higher cluster
    float threshold = 0.f;  ///< values above this belong to the higher cluster
    int low_count = 0;
    int high_count = 0;
    int iterations = 0;
};

/// Histogram of values in [0, max_value] (larger values count in the last bin), `bins` bins.
class Histogram {
  public:
    Histogram(float max_value, int bins);
    void add(float value) {
        if (!(value >= 0.f)) value = 0.f;  // NaN and negatives count as 0
        const int last = static_cast<int>(bins_.size()) - 1;
        const int b =
            value >= max_value_ ? last : std::min(last, static_cast<int>(value / bin_width_));
        ++bins_[static_cast<size_t>(b)];
        ++count_;
    }
    /// Adds another histogram's counts (same max_value and bins; e.g. one per row block).
    void add(const Histogram& other);
    int count() const { return count_; }
    /// 2-means of what was added: starts from the lowest and highest non-empty bins and
    /// iterates until the split stops moving (at most `max_iterations`). With fewer than two
    /// non-empty bins both centroids are the one value and high_count is 0.
    TwoMeans two_means(int max_iterations = 20) const;
    /// The value below which a fraction q (0..1) of what was added lies (the upper edge of the
    /// bin that reaches it); 0 when nothing was added.
    float quantile(float q) const;

  private:
    float max_value_;
    float bin_width_;
    std::vector<int> bins_;
    int count_ = 0;
};

/// two_means over `values` with a histogram of `bins` bins over [0, max_value].
TwoMeans two_means(const std::vector<float>& values, float max_value, int bins = 256);

}  // namespace df::dynamics
