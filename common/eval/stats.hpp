#pragma once
/// Summary statistics of a list of errors, with numpy's semantics (as TUM's tools print them).
#include <cstddef>
#include <vector>

namespace df::eval {

inline constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

/// Statistics of non-negative errors in one unit (metres, degrees, milliseconds...).
struct ErrorStats {
    size_t count = 0;
    double rmse = 0;  ///< sqrt(sum e^2 / n)
    double mean = 0;
    double median = 0;  ///< mean of the two middle values for an even count (numpy.median)
    double stddev = 0;  ///< population standard deviation (numpy.std, ddof = 0)
    double min = 0;
    double max = 0;
};

/// All fields zero for an empty list.
ErrorStats summarize_errors(const std::vector<double>& values);

/// Percentile q in [0, 100], linear interpolation between closest ranks (numpy.percentile's
/// default). 0 for an empty list.
double percentile(std::vector<double> values, double q);

}  // namespace df::eval
