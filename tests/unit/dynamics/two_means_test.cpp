#include <gtest/gtest.h>

#include <random>

#include "dynamics/two_means.hpp"

namespace df::dynamics {
namespace {

TEST(TwoMeans, SplitsTwoSeparatedClustersAtTheGap) {
    std::mt19937 rng(3);
    std::normal_distribution<float> low(0.005f, 0.002f), high(0.12f, 0.01f);
    std::vector<float> v;
    for (int i = 0; i < 9000; ++i) v.push_back(std::max(0.f, low(rng)));
    for (int i = 0; i < 1000; ++i) v.push_back(high(rng));
    const TwoMeans m = two_means(v, 0.2f);
    EXPECT_NEAR(m.low, 0.005f, 0.002f);
    EXPECT_NEAR(m.high, 0.12f, 0.004f);
    EXPECT_GT(m.threshold, 0.02f);
    EXPECT_LT(m.threshold, 0.09f);
    EXPECT_EQ(m.low_count, 9000);
    EXPECT_EQ(m.high_count, 1000);
}

TEST(TwoMeans, ValuesBeyondTheRangeCountInTheLastBin) {
    std::vector<float> v(100, 0.01f);
    v.insert(v.end(), 10, 5.f);  // far beyond max_value
    const TwoMeans m = two_means(v, 0.2f);
    EXPECT_EQ(m.high_count, 10);
    EXPECT_GT(m.high, 0.19f);
}

TEST(TwoMeans, OneValueGivesOneClusterAndNoHighPixels) {
    const TwoMeans m = two_means(std::vector<float>(50, 0.03f), 0.2f);
    EXPECT_EQ(m.high_count, 0);
    EXPECT_NEAR(m.low, 0.03f, 0.001f);
    EXPECT_FLOAT_EQ(m.low, m.high);
    const TwoMeans none = two_means({}, 0.2f);
    EXPECT_EQ(none.low_count + none.high_count, 0);
}

}  // namespace
}  // namespace df::dynamics
