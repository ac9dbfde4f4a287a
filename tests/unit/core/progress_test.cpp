// What `df_slam offline` and `df_make_sequence` show of their progress.
#include "core/progress.hpp"

#include <gtest/gtest.h>

namespace df {
namespace {

TEST(Progress, SaysDoneTotalRateAndTimeLeft) {
    // 120 of 900 frames in 10 s: 12 frames/s, 780 left = 65 s.
    EXPECT_EQ(Progress::text("frames", 120, 900, 10.0), "120/900 frames (13 %)  12.0/s  1:05 left");
    EXPECT_EQ(Progress::text("frames", 900, 900, 60.0),
              "900/900 frames (100 %)  15.0/s  0:00 left");
    // Over an hour left.
    EXPECT_EQ(Progress::text("frames", 1, 10000, 1.0), "1/10000 frames (0 %)  1.0/s  2:46:39 left");
}

TEST(Progress, WithoutATotalSaysDoneRateAndTimeSpent) {
    EXPECT_EQ(Progress::text("frames", 300, -1, 20.0), "300 frames  15.0/s  0:20");
}

TEST(Progress, NothingDoneYetHasNoRate) {
    EXPECT_EQ(Progress::text("frames", 0, 50, 0.0), "0/50 frames (0 %)  0.0/s  0:00 left");
}

}  // namespace
}  // namespace df
