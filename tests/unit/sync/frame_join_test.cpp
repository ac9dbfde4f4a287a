// FrameJoin driven by tables: segments (S) and detections (D) arriving at given milliseconds,
// frames captured at 30 Hz (frame k at k * 33.333 ms); the clock is polled every millisecond.
// Each table lists what is published for each frame, when, and with which frame's detections.
#include "sync/frame_join.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace df::sync {
namespace {

constexpr int64_t kMs = 1'000'000;

struct Event {
    int t_ms;
    char topic;  // 'S' segments, 'D' detections
    uint64_t seq;
    Arrival status = Arrival::kOk;
};

struct Expected {
    uint64_t seq;
    int at_ms;
    int detections_seq;  // -1: published without detections
    Arrival segments = Arrival::kOk;
};

int64_t capture_ns(uint64_t seq) { return static_cast<int64_t>(seq) * 100 * kMs / 3; }

std::vector<Expected> run(const std::vector<Event>& events, int until_ms,
                          const JoinConfig& config = {}, FrameJoin* out_join = nullptr) {
    FrameJoin local(config);
    FrameJoin& join = out_join ? *out_join : local;
    std::vector<Expected> got;
    size_t next = 0;
    for (int t = 0; t <= until_ms; ++t) {
        for (; next < events.size() && events[next].t_ms == t; ++next) {
            const Event& e = events[next];
            if (e.topic == 'S') {
                join.on_segments(e.seq, capture_ns(e.seq), e.status, t * kMs);
            } else {
                join.on_detections(e.seq, capture_ns(e.seq), e.status, t * kMs);
            }
        }
        for (const JoinDecision& d : join.poll(t * kMs)) {
            got.push_back({d.seq, t, d.detections_used ? static_cast<int>(d.detections_seq) : -1,
                           d.segments});
        }
    }
    EXPECT_EQ(next, events.size()) << "events not sorted by time";
    return got;
}

std::string show(const std::vector<Expected>& v) {
    std::string s;
    for (const Expected& e : v) {
        s += "(frame " + std::to_string(e.seq) + " at " + std::to_string(e.at_ms) + " ms, dets " +
             std::to_string(e.detections_seq) + ") ";
    }
    return s;
}

void expect_table(const std::vector<Expected>& got, const std::vector<Expected>& want) {
    ASSERT_EQ(got.size(), want.size()) << "got " << show(got) << "\nwant " << show(want);
    for (size_t i = 0; i < want.size(); ++i) {
        EXPECT_EQ(got[i].seq, want[i].seq) << i;
        EXPECT_EQ(got[i].at_ms, want[i].at_ms) << "frame " << want[i].seq;
        EXPECT_EQ(got[i].detections_seq, want[i].detections_seq) << "frame " << want[i].seq;
        EXPECT_EQ(got[i].segments, want[i].segments) << "frame " << want[i].seq;
    }
}

TEST(FrameJoin, DetectionsInTimeArePairedWithTheirFrame) {
    expect_table(run({{0, 'S', 0}, {20, 'D', 0}, {33, 'S', 1}, {50, 'D', 1}}, 200),
                 {{0, 20, 0}, {1, 50, 1}});
}

TEST(FrameJoin, LateDetectionsReleaseTheFrameAtTheDeadlineAndAreReusedLater) {
    // Frame 0's detections come 80 ms late: frame 0 goes at 60 ms without; frame 1 (deadline
    // 93 ms, no detections of its own) reuses them, frame 0 being 33 ms older.
    expect_table(run({{0, 'S', 0}, {33, 'S', 1}, {80, 'D', 0}}, 300), {{0, 60, -1}, {1, 93, 0}});
}

TEST(FrameJoin, MissingDetectorNeverStallsTheFrames) {
    expect_table(run({{0, 'S', 0}, {33, 'S', 1}, {67, 'S', 2}}, 300),
                 {{0, 60, -1}, {1, 93, -1}, {2, 127, -1}});
}

TEST(FrameJoin, DetectionsBeforeTheirSegmentsWait) {
    // Reordered: frame 1's detections come first, then frame 0's segments are late too.
    expect_table(run({{0, 'S', 0}, {10, 'D', 1}, {33, 'S', 1}, {40, 'D', 0}}, 200),
                 {{0, 40, 0}, {1, 40, 1}});
}

TEST(FrameJoin, DuplicatesAreIgnoredAndCounted) {
    FrameJoin join;
    expect_table(
        run({{0, 'S', 0}, {5, 'S', 0}, {10, 'D', 0}, {12, 'D', 0}, {15, 'S', 0}}, 100, {}, &join),
        {{0, 10, 0}});
    EXPECT_EQ(join.duplicates(), 2u);  // the second S before release; the late S after is too
}

TEST(FrameJoin, FramesLeaveInOrderBehindALateOne) {
    // Frame 1's detections are there at 40 ms, but frame 0 waits for its deadline (60 ms).
    expect_table(run({{0, 'S', 0}, {33, 'S', 1}, {40, 'D', 1}}, 200), {{0, 60, -1}, {1, 60, 1}});
}

TEST(FrameJoin, SkippedDetectionsReleaseAtOnceAndReuseTheLastBoxes) {
    expect_table(
        run({{0, 'S', 0}, {10, 'D', 0}, {33, 'S', 1}, {35, 'D', 1, Arrival::kSkipped}}, 200),
        {{0, 10, 0}, {1, 35, 0}});
}

TEST(FrameJoin, SkippedSegmentsAreReleasedAtOnceMarkedSo) {
    expect_table(run({{0, 'S', 0, Arrival::kSkipped}, {1, 'D', 0}}, 100),
                 {{0, 0, -1, Arrival::kSkipped}});
}

TEST(FrameJoin, DetectionsTooOldAreNotReused) {
    // Frame 4 is captured 133 ms after frame 0: older than reuse_max_age (100 ms).
    expect_table(run({{0, 'S', 0}, {10, 'D', 0}, {140, 'S', 4}}, 300), {{0, 10, 0}, {4, 200, -1}});
}

TEST(FrameJoin, TooManyWaitingFramesReleaseTheOldest) {
    JoinConfig config;
    config.detection_deadline_ms = 1000;
    config.max_pending = 2;
    expect_table(run({{0, 'S', 0}, {1, 'S', 1}, {2, 'S', 2}, {3, 'S', 3}}, 10, config),
                 {{0, 2, -1}, {1, 3, -1}});
}

TEST(FrameJoin, NextDeadlineTellsWhenToPoll) {
    FrameJoin join;
    EXPECT_FALSE(join.next_deadline_ns().has_value());
    join.on_segments(7, capture_ns(7), Arrival::kOk, 5 * kMs);
    ASSERT_TRUE(join.next_deadline_ns().has_value());
    EXPECT_EQ(*join.next_deadline_ns(), 65 * kMs);
    EXPECT_TRUE(join.poll(64 * kMs).empty());
    EXPECT_EQ(join.poll(65 * kMs).size(), 1u);
    EXPECT_EQ(join.pending(), 0u);
}

TEST(FrameJoin, BadConfigIsNamed) {
    JoinConfig c;
    c.detection_deadline_ms = -1;
    EXPECT_EQ(validate(c), "detection_deadline_ms is -1, allowed: >= 0 and <= 600000 [ms]");
    EXPECT_TRUE(validate(JoinConfig{}).empty());
}

// A restarted capture counts from 0 again in a new epoch: the join starts over.
TEST(FrameJoin, ANewRunIsNeverTakenForDuplicates) {
    FrameJoin join;
    std::vector<JoinDecision> released;
    std::vector<JoinDecision> got;
    int t = 0;
    for (uint64_t epoch : {100u, 200u}) {
        for (uint64_t seq = 0; seq < 3; ++seq, t += 33) {
            EXPECT_NE(join.on_epoch(epoch, t * kMs, &released), EpochCheck::kStale);
            join.on_segments(seq, capture_ns(seq), Arrival::kOk, t * kMs);
            join.on_detections(seq, capture_ns(seq), Arrival::kOk, t * kMs);
            for (const JoinDecision& d : join.poll(t * kMs)) got.push_back(d);
        }
    }
    EXPECT_TRUE(released.empty());  // nothing was waiting when the second run began
    ASSERT_EQ(got.size(), 6u);
    EXPECT_EQ(join.duplicates(), 0u);
    for (size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].seq, i % 3);
        EXPECT_EQ(got[i].epoch, i < 3 ? 100u : 200u);
        EXPECT_TRUE(got[i].detections_used);
        EXPECT_EQ(got[i].detections_seq, got[i].seq);
    }
}

TEST(FrameJoin, FramesWaitingWhenANewRunBeginsAreReleasedAsTheOldRunsLast) {
    FrameJoin join;
    std::vector<JoinDecision> released;
    ASSERT_EQ(join.on_epoch(100, 0, &released), EpochCheck::kNewRun);
    join.on_segments(7, capture_ns(7), Arrival::kOk, 0);
    join.on_detections(6, capture_ns(6), Arrival::kOk, 0);  // late boxes of frame 6
    join.on_segments(8, capture_ns(8), Arrival::kOk, 0);
    ASSERT_EQ(join.on_epoch(200, 1 * kMs, &released), EpochCheck::kNewRun);
    ASSERT_EQ(released.size(), 2u);
    EXPECT_EQ(released[0].seq, 7u);
    EXPECT_EQ(released[0].epoch, 100u);
    EXPECT_TRUE(released[0].detections_used);  // frame 6's boxes, 33 ms older
    EXPECT_EQ(released[0].detections_seq, 6u);
    EXPECT_EQ(released[1].seq, 8u);
    EXPECT_TRUE(released[1].detections_used);
    EXPECT_EQ(released[1].detections_seq, 6u);
    EXPECT_EQ(join.pending(), 0u);
    // The new run's frame 7 is a frame of its own, and the old run's boxes are not reused.
    join.on_segments(7, capture_ns(7), Arrival::kOk, 2 * kMs);
    const auto d =
        join.poll(2 * kMs + static_cast<int64_t>(JoinConfig{}.detection_deadline_ms * kMs));
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].seq, 7u);
    EXPECT_EQ(d[0].epoch, 200u);
    EXPECT_FALSE(d[0].detections_used);
    EXPECT_EQ(join.duplicates(), 0u);
}

TEST(FrameJoin, MessagesOfAnEarlierRunAreStale) {
    FrameJoin join;
    std::vector<JoinDecision> released;
    EXPECT_EQ(join.on_epoch(200, 0, &released), EpochCheck::kNewRun);
    EXPECT_EQ(join.on_epoch(200, 0, &released), EpochCheck::kCurrent);
    EXPECT_EQ(join.on_epoch(100, 0, &released), EpochCheck::kStale);
    EXPECT_EQ(join.stale(), 1u);
    EXPECT_EQ(join.epoch(), std::optional<uint64_t>(200));
    EXPECT_TRUE(released.empty());
}

}  // namespace
}  // namespace df::sync
