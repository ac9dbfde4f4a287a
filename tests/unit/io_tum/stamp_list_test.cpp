// Parsing rgb.txt/depth.txt/associations.txt and associating stamps as TUM's associate.py does.
#include <gtest/gtest.h>

#include <cmath>

#include "io/tum/tum_folder.hpp"
#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::TempFolder;
using test::write_file;

/// Test data written in seconds, as nanoseconds (the nearest integer).
int64_t ns(double seconds) { return std::llround(seconds * 1e9); }

std::vector<StampedPath> stamps(std::initializer_list<double> values) {
    std::vector<StampedPath> out;
    for (double v : values) out.push_back({ns(v), std::to_string(v) + ".png", 0});
    return out;
}

TEST(ParseStampList, ReadsEntriesSkippingCommentsAndBlankLines) {
    TempFolder tmp;
    write_file(tmp / "rgb.txt",
               "# color images\n"
               "# timestamp filename\n"
               "\n"
               "1305031102.175304 rgb/1305031102.175304.png\n"
               "   \t\n"
               "1305031102.211214\trgb/b.png\r\n"
               "1305031102.243211 rgb/c.png extra tokens are ignored\n");
    auto parsed = parse_stamp_list(tmp / "rgb.txt");
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    EXPECT_TRUE(parsed->errors.empty());
    ASSERT_EQ(parsed->entries.size(), 3u);
    EXPECT_EQ(parsed->entries[0].stamp_ns, 1305031102175304000);  // exact
    EXPECT_EQ(parsed->entries[0].path, "rgb/1305031102.175304.png");
    EXPECT_EQ(parsed->entries[0].line, 4);
    EXPECT_EQ(parsed->entries[1].path, "rgb/b.png");  // tab separated, CRLF ending
    EXPECT_EQ(parsed->entries[1].line, 6);
    EXPECT_EQ(parsed->entries[2].path, "rgb/c.png");
}

TEST(ParseStampList, MalformedLinesAreSkippedWithFileAndLine) {
    TempFolder tmp;
    const std::string file = tmp / "depth.txt";
    write_file(file,
               "# depth maps\n"
               "1.0 depth/1.png\n"
               "abc depth/2.png\n"
               "2.0\n"
               "-3.0 depth/3.png\n"
               "nan depth/4.png\n"
               "inf depth/5.png\n"
               "6.0x depth/6.png\n"
               "7.0 depth/7.png\n");
    auto parsed = parse_stamp_list(file);
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    ASSERT_EQ(parsed->entries.size(), 2u);
    EXPECT_EQ(parsed->entries[0].path, "depth/1.png");
    EXPECT_EQ(parsed->entries[1].path, "depth/7.png");
    EXPECT_EQ(parsed->entries[1].line, 9);
    ASSERT_EQ(parsed->errors.size(), 6u);
    EXPECT_EQ(parsed->errors[0].rfind(file + ":3: ", 0), 0u) << parsed->errors[0];
    EXPECT_NE(parsed->errors[0].find("'abc'"), std::string::npos) << parsed->errors[0];
    EXPECT_EQ(parsed->errors[1].rfind(file + ":4: expected 'timestamp path'", 0), 0u)
        << parsed->errors[1];
    EXPECT_EQ(parsed->errors[2].rfind(file + ":5: ", 0), 0u) << parsed->errors[2];
    EXPECT_EQ(parsed->errors[3].rfind(file + ":6: ", 0), 0u) << parsed->errors[3];
    EXPECT_EQ(parsed->errors[4].rfind(file + ":7: ", 0), 0u) << parsed->errors[4];
    EXPECT_EQ(parsed->errors[5].rfind(file + ":8: ", 0), 0u) << parsed->errors[5];
}

TEST(ParseStampList, MissingFileIsAnErrorNamingIt) {
    TempFolder tmp;
    auto parsed = parse_stamp_list(tmp / "nope.txt");
    ASSERT_FALSE(parsed);
    EXPECT_EQ(parsed.status().code(), StatusCode::kNotFound);
    EXPECT_NE(parsed.status().message().find(tmp / "nope.txt"), std::string::npos);
}

TEST(ParseAssociations, ReadsPairsAndReportsMalformedLines) {
    TempFolder tmp;
    const std::string file = tmp / "associations.txt";
    write_file(file,
               "1.0 rgb/1.png 1.01 depth/1.png\n"
               "2.0 rgb/2.png 2.01\n"
               "3.0 rgb/3.png x depth/3.png\n"
               "4.0 rgb/4.png 4.0 depth/4.png\n");
    auto parsed = parse_associations(file);
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    ASSERT_EQ(parsed->pairs.size(), 2u);
    EXPECT_EQ(parsed->pairs[0].rgb.path, "rgb/1.png");
    EXPECT_EQ(parsed->pairs[0].depth.stamp_ns, ns(1.01));
    EXPECT_EQ(parsed->pairs[0].depth.path, "depth/1.png");
    EXPECT_EQ(parsed->pairs[1].rgb.line, 4);
    ASSERT_EQ(parsed->errors.size(), 2u);
    EXPECT_EQ(parsed->errors[0].rfind(file + ":2: expected 't_rgb rgb_path t_depth depth_path'", 0),
              0u)
        << parsed->errors[0];
    EXPECT_EQ(parsed->errors[1].rfind(file + ":3: ", 0), 0u) << parsed->errors[1];
    EXPECT_NE(parsed->errors[1].find("'x'"), std::string::npos) << parsed->errors[1];
}

TEST(Associate, MatchesWithinWindowAndDropsFartherOnes) {
    const auto pairs = associate(stamps({1.0, 2.0, 3.0}), stamps({1.015, 2.03, 2.999}), ns(0.02));
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0].rgb.stamp_ns, ns(1.0));
    EXPECT_EQ(pairs[0].depth.stamp_ns, ns(1.015));
    EXPECT_EQ(pairs[1].rgb.stamp_ns, ns(3.0));
    EXPECT_EQ(pairs[1].depth.stamp_ns, ns(2.999));
}

TEST(Associate, WindowIsStrict) {
    // Exactly representable stamps: a difference equal to the window is not a match.
    EXPECT_TRUE(associate(stamps({0.5}), stamps({0.75}), ns(0.25)).empty());
    EXPECT_EQ(associate(stamps({0.5}), stamps({0.625}), ns(0.25)).size(), 1u);
}

TEST(Associate, GreedyBySmallestDifferenceOneToOne) {
    // Candidates: (1.010, 1.008) 0.002, (1.000, 1.008) 0.008, (1.010, 1.030) 0.020.
    // Greedy takes 0.002 first, which uses up both 1.010 and 1.008, so nothing else is left:
    // associate.py yields one pair here (an optimal assignment would yield two).
    const auto pairs = associate(stamps({1.000, 1.010}), stamps({1.008, 1.030}), ns(0.025));
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].rgb.stamp_ns, ns(1.010));
    EXPECT_EQ(pairs[0].depth.stamp_ns, ns(1.008));
}

TEST(Associate, EachStampUsedOnceAndResultSortedByRgbStamp) {
    // Three rgb stamps near one depth stamp: only the closest gets it. Input order is shuffled.
    const auto pairs =
        associate(stamps({5.0, 1.004, 1.0, 0.995}), stamps({4.99, 1.001, 9.0}), ns(0.02));
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0].rgb.stamp_ns, ns(1.0));
    EXPECT_EQ(pairs[0].depth.stamp_ns, ns(1.001));
    EXPECT_EQ(pairs[1].rgb.stamp_ns, ns(5.0));
    EXPECT_EQ(pairs[1].depth.stamp_ns, ns(4.99));
    EXPECT_EQ(pairs[1].rgb.path, stamps({5.0})[0].path);
}

TEST(Associate, TypicalTumRatesPairEveryFrame) {
    // 30 Hz rgb and depth with a 7 ms offset: every rgb frame gets the depth frame next to it.
    std::vector<StampedPath> rgb, depth;
    for (int i = 0; i < 300; ++i) {
        rgb.push_back({ns(100.0 + i / 30.0), "r", i});
        depth.push_back({ns(100.007 + i / 30.0), "d", i});
    }
    const auto pairs = associate(rgb, depth, ns(0.02));
    ASSERT_EQ(pairs.size(), 300u);
    for (int i = 0; i < 300; ++i) {
        EXPECT_EQ(pairs[i].rgb.line, i);
        EXPECT_EQ(pairs[i].depth.line, i);
    }
}

TEST(IntrinsicsPreset, KnownNamesAndAnErrorListingThem) {
    auto fr1 = intrinsics_preset("fr1");
    ASSERT_TRUE(fr1);
    EXPECT_DOUBLE_EQ(fr1->fx, 517.3);
    EXPECT_DOUBLE_EQ(fr1->cy, 255.3);
    auto fr2 = intrinsics_preset("fr2");
    ASSERT_TRUE(fr2);
    EXPECT_DOUBLE_EQ(fr2->fy, 521.0);
    auto fr3 = intrinsics_preset("fr3");
    ASSERT_TRUE(fr3);
    EXPECT_DOUBLE_EQ(fr3->fx, 535.4);
    EXPECT_DOUBLE_EQ(fr3->fy, 539.2);
    EXPECT_DOUBLE_EQ(fr3->cx, 320.1);
    EXPECT_DOUBLE_EQ(fr3->cy, 247.6);
    auto scenes = intrinsics_preset("7scenes");
    ASSERT_TRUE(scenes);
    EXPECT_DOUBLE_EQ(scenes->fx, 585.0);
    EXPECT_DOUBLE_EQ(scenes->cx, 320.0);

    auto unknown = intrinsics_preset("fr4");
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
    for (const char* name : {"fr4", "fr1", "fr2", "fr3", "7scenes"}) {
        EXPECT_NE(unknown.status().message().find(name), std::string::npos)
            << unknown.status().message();
    }
}

}  // namespace
}  // namespace df::io
