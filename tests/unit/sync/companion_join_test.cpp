// The SLAM service's join of a frame with its object and geometric segments, driven by arrival
// times (ms): complete frames go at once, late ones at the deadline, a stream without writers is
// not waited for, frames come out in order.
#include <gtest/gtest.h>

#include "sync/companion_join.hpp"

namespace df::sync {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(CompanionJoin, ACompleteFrameIsReadyAtOnceWithItsPayloads) {
    CompanionJoin j(2, 100 * kMs, 30);
    j.on_frame(0, 0);
    EXPECT_TRUE(j.poll(1 * kMs).empty());
    j.on_companion(0, 0, true);
    EXPECT_TRUE(j.poll(2 * kMs).empty());
    j.on_companion(1, 0, false);  // answered, failed: no payload, but no wait either
    const auto r = j.poll(3 * kMs);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].seq, 0u);
    EXPECT_FALSE(r[0].late);
    EXPECT_TRUE(r[0].ok[0]);
    EXPECT_FALSE(r[0].ok[1]);
}

TEST(CompanionJoin, SegmentsThatStopComingCostTheDeadlineOnly) {
    CompanionJoin j(2, 100 * kMs, 30);
    j.on_frame(5, 0);
    j.on_companion(1, 5, true);
    EXPECT_TRUE(j.poll(99 * kMs).empty());
    const auto r = j.poll(100 * kMs);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_TRUE(r[0].late);
    EXPECT_FALSE(r[0].ok[0]);
    EXPECT_TRUE(r[0].ok[1]);
}

TEST(CompanionJoin, AStreamWithoutWritersIsNotWaitedFor) {
    CompanionJoin j(2, 100 * kMs, 30);
    j.set_expected(0, false);
    j.set_expected(1, false);
    j.on_frame(0, 0);
    const auto r = j.poll(0);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_FALSE(r[0].late);
    EXPECT_FALSE(r[0].ok[0]);
}

TEST(CompanionJoin, CompanionsBeforeTheirFrameAndFramesInOrder) {
    CompanionJoin j(1, 100 * kMs, 30);
    j.on_companion(0, 2, true);  // before frame 2 itself
    j.on_frame(1, 0);
    j.on_frame(2, 1 * kMs);
    // Frame 2 is complete but waits for frame 1, which is not.
    EXPECT_TRUE(j.poll(2 * kMs).empty());
    j.on_companion(0, 1, true);
    const auto r = j.poll(3 * kMs);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].seq, 1u);
    EXPECT_EQ(r[1].seq, 2u);
    EXPECT_TRUE(r[1].ok[0]);
}

TEST(CompanionJoin, TooManyWaitingReleasesTheOldestAndResetForgets) {
    CompanionJoin j(1, 1000 * kMs, 2);
    j.on_frame(0, 0);
    j.on_frame(1, 0);
    j.on_frame(2, 0);
    const auto r = j.poll(1 * kMs);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].seq, 0u);
    EXPECT_TRUE(r[0].late);
    j.reset();
    EXPECT_EQ(j.pending(), 0u);
}

}  // namespace
}  // namespace df::sync
