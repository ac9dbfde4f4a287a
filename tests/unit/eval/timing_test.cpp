// Timing lines: format, parse, statistics.
#include "eval/timing.hpp"

#include <gtest/gtest.h>

#include "eval_test_support.hpp"

namespace df::eval {
namespace {

TEST(Timing, FormattedLinesParseBackInsideLoggerLines) {
    const std::string line =
        format_timing_line(12, "slam", {{"preprocess", 3.1}, {"tracking", 20.5}});
    EXPECT_EQ(line, "timing seq=12 stage=slam preprocess=3.100 tracking=20.500");
    auto parsed = parse_timing_line("2026-11-24T10:00:00.123 [info] slam: " + line);
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    ASSERT_TRUE(parsed->has_value());
    const TimingSample& s = **parsed;
    EXPECT_EQ(s.seq, 12);
    EXPECT_EQ(s.stage, "slam");
    ASSERT_EQ(s.steps_ms.size(), 2u);
    EXPECT_EQ(s.steps_ms[1].first, "tracking");
    EXPECT_DOUBLE_EQ(s.steps_ms[1].second, 20.5);
}

TEST(Timing, OtherLinesAreIgnoredAndMalformedRecordsReported) {
    auto prose = parse_timing_line("[warn] capture: timing out waiting for frames");
    ASSERT_TRUE(prose);
    EXPECT_FALSE(prose->has_value());
    EXPECT_FALSE(parse_timing_line("timing seq=x stage=slam a=1"));
    EXPECT_FALSE(parse_timing_line("timing seq=3 slam a=1"));
    EXPECT_FALSE(parse_timing_line("timing seq=3 stage=slam a=fast"));
    EXPECT_FALSE(parse_timing_line("timing seq=3 stage=slam"));
}

TEST(Timing, StatisticsPerStageAndStep) {
    test::TempFolder tmp;
    std::string log = "starting\n";
    for (int i = 1; i <= 20; ++i) {
        log += "[info] seg: " +
               format_timing_line(i, "seg", {{"net", double(i)}, {"total", 2.0 * i}}) + "\n";
    }
    log += "[info] seg: timing seq=21 stage=seg net=oops\n";
    test::write_file(tmp / "run.log", log);
    auto parsed = read_timing_log(tmp / "run.log");
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    EXPECT_EQ(parsed->samples.size(), 20u);
    ASSERT_EQ(parsed->errors.size(), 1u);
    EXPECT_NE(parsed->errors[0].find("run.log:22:"), std::string::npos) << parsed->errors[0];
    const auto stats = summarize_timing(parsed->samples);
    ASSERT_EQ(stats.size(), 2u);
    EXPECT_EQ(stats[0].step, "net");
    EXPECT_EQ(stats[0].count, 20u);
    EXPECT_DOUBLE_EQ(stats[0].mean_ms, 10.5);
    EXPECT_DOUBLE_EQ(stats[0].median_ms, 10.5);
    EXPECT_NEAR(stats[0].p95_ms, 19.05, 1e-12);  // numpy.percentile(range(1, 21), 95)
    EXPECT_DOUBLE_EQ(stats[1].max_ms, 40.0);
}

}  // namespace
}  // namespace df::eval
