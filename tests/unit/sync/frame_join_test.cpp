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
    config.detection_deadline_ns = 1000 * kMs;
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
    c.detection_deadline_ns = -1;
    EXPECT_NE(validate(c).find("detection_deadline_ns"), std::string::npos);
    EXPECT_TRUE(validate(JoinConfig{}).empty());
}

}  // namespace
}  // namespace df::sync
