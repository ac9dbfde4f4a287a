#include "sync/seq_gaps.hpp"

#include <gtest/gtest.h>

namespace df::sync {
namespace {

using Seqs = std::vector<uint64_t>;

TEST(SeqGaps, FramesLostBetweenTwoArrivalsAreNamedInOrder) {
    SeqGaps gaps;
    EXPECT_EQ(gaps.arrived(7, 0), Seqs{});
    EXPECT_EQ(gaps.arrived(7, 1), Seqs{});
    EXPECT_EQ(gaps.arrived(7, 5), (Seqs{2, 3, 4}));
    EXPECT_EQ(gaps.arrived(7, 6), Seqs{});
    EXPECT_EQ(gaps.missed(), 3u);
}

TEST(SeqGaps, TheFirstFrameSeenMissesNothing) {
    SeqGaps gaps;  // a stage that started late did not miss the frames before it
    EXPECT_EQ(gaps.arrived(7, 40), Seqs{});
    EXPECT_EQ(gaps.arrived(7, 42), Seqs{41});
}

TEST(SeqGaps, ANewRunStartsAfresh) {
    SeqGaps gaps;
    gaps.arrived(7, 10);
    EXPECT_EQ(gaps.arrived(8, 3), Seqs{});  // restarted capture: epoch 8 begins at 3 (resumed)
    EXPECT_EQ(gaps.arrived(8, 5), Seqs{4});
}

TEST(SeqGaps, RepeatsAndOlderFramesMissNothingAndDoNotMoveBack) {
    SeqGaps gaps;
    gaps.arrived(1, 10);
    EXPECT_EQ(gaps.arrived(1, 10), Seqs{});
    EXPECT_EQ(gaps.arrived(1, 4), Seqs{});
    EXPECT_EQ(gaps.arrived(1, 12), Seqs{11});
}

TEST(SeqGaps, AHugeJumpIsNotAnsweredFrameByFrame) {
    SeqGaps gaps;
    gaps.arrived(1, 0);
    EXPECT_EQ(gaps.arrived(1, 1'000'000'000'000ull), Seqs{});
    EXPECT_EQ(gaps.arrived(1, 1'000'000'000'002ull), Seqs{1'000'000'000'001ull});
    gaps.arrived(1, 2'000'000'000'000ull + SeqGaps::kMaxGap + 1);
    EXPECT_EQ(gaps.missed(), 1u);
}

}  // namespace
}  // namespace df::sync
