// Exact TUM stamps: decimal seconds to integer nanoseconds with no floating point, nanosecond
// files recognised, every stamp out of range refused naming file and line.
#include "io/tum/stamp.hpp"

#include <gtest/gtest.h>

#include "io/tum/trajectory.hpp"
#include "io/tum/tum_folder.hpp"
#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::TempFolder;
using test::contains;
using test::write_file;

int64_t ns_of(const std::string& field) {
    auto stamp = parse_stamp(field);
    EXPECT_TRUE(stamp) << field << ": " << stamp.status().message();
    return stamp ? stamp->ns : -1;
}

TEST(ParseStamp, DecimalSecondsAreExactNanoseconds) {
    EXPECT_EQ(ns_of("1305031102.175304"), 1305031102175304000);
    // The double nearest 1305031102.175304 is 1305031102.1753039360...: no rounding here.
    EXPECT_EQ(ns_of("1305031102.175304001"), 1305031102175304001);
    EXPECT_EQ(ns_of("0"), 0);
    EXPECT_EQ(ns_of("0.000000001"), 1);
    EXPECT_EQ(ns_of(".5"), 500000000);
    EXPECT_EQ(ns_of("7."), 7000000000);
    EXPECT_EQ(ns_of("9223372036.854775807"), INT64_MAX);  // the last representable ns
    EXPECT_EQ(parse_stamp("1.5")->unit, StampUnit::kSeconds);
}

TEST(ParseStamp, NineteenDigitIntegersAreNanoseconds) {
    auto stamp = parse_stamp("1305031102175304123");
    ASSERT_TRUE(stamp) << stamp.status().message();
    EXPECT_EQ(stamp->ns, 1305031102175304123);
    EXPECT_EQ(stamp->unit, StampUnit::kNanoseconds);
    // A 10-digit integer is seconds.
    EXPECT_EQ(ns_of("1305031102"), 1305031102000000000);
    EXPECT_EQ(parse_stamp("1305031102")->unit, StampUnit::kSeconds);
}

TEST(ParseStamp, OutOfRangeAndGarbageAreRefusedSayingWhy) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"-1.0", "negative"},
        {"nan", "not a decimal number"},
        {"inf", "not a decimal number"},
        {"1e300", "not a decimal number"},
        {"1.5e9", "not a decimal number"},
        {"+1.0", "not a decimal number"},
        {"12abc", "not a decimal number"},
        {"1.2.3", "not a decimal number"},
        {"", "empty"},
        {".", "no digits"},
        {"1.0000000001", "10 decimals"},
        {"9223372036.854775808", "beyond year 2262"},  // one ns past int64
        {"9223372037", "beyond year 2262"},            // seconds
        {"99999999999", "beyond year 2262"},           // 11 digits: too large for seconds
        {"9223372036854775808", "beyond year 2262"},   // ns, one past int64
        {"99999999999999999999999", "beyond year 2262"},
    };
    for (const auto& [field, why] : cases) {
        auto stamp = parse_stamp(field);
        ASSERT_FALSE(stamp) << field << " gave " << stamp->ns;
        EXPECT_TRUE(contains(stamp.status().message(), why))
            << field << ": " << stamp.status().message();
        EXPECT_TRUE(contains(stamp.status().message(), "9223372036.854775807 s"))
            << stamp.status().message();  // the allowed range is named
    }
}

TEST(StampText, FormatsIntegerNanosecondsAsSecondsRoundedHalfUp) {
    EXPECT_EQ(stamp_text(1305031102175304000), "1305031102.175304");
    EXPECT_EQ(stamp_text(1305031102175304499), "1305031102.175304");
    EXPECT_EQ(stamp_text(1305031102175304500), "1305031102.175305");
    EXPECT_EQ(stamp_text(999999500), "1.000000");
    EXPECT_EQ(stamp_text(0), "0.000000");
    EXPECT_EQ(stamp_text(INT64_MAX, 9), "9223372036.854775807");
    EXPECT_EQ(stamp_text(1500000000, 0), "2");
    // Round trip through the parser.
    EXPECT_EQ(ns_of(stamp_text(1305031102175304000)), 1305031102175304000);
}

TEST(StampList, NanosecondFileIsReadExactly) {
    TempFolder tmp;
    const std::string file = tmp / "rgb.txt";
    write_file(file,
               "# recorder writing nanoseconds\n"
               "1305031102175304123 rgb/a.png\n"
               "1305031102208637456 rgb/b.png\n");
    auto parsed = parse_stamp_list(file);
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    EXPECT_TRUE(parsed->errors.empty()) << parsed->errors.front();
    ASSERT_EQ(parsed->entries.size(), 2u);
    EXPECT_EQ(parsed->entries[0].stamp_ns, 1305031102175304123);
    EXPECT_EQ(parsed->entries[1].stamp_ns, 1305031102208637456);
}

TEST(StampList, MixedUnitsAndOutOfRangeStampsNameFileAndLine) {
    TempFolder tmp;
    const std::string file = tmp / "depth.txt";
    write_file(file,
               "1305031102175304123 depth/a.png\n"
               "1305031102.2 depth/b.png\n"
               "1e300 depth/c.png\n"
               "-5 depth/d.png\n"
               "99999999999 depth/e.png\n"
               "1305031102241970000 depth/f.png\n");
    auto parsed = parse_stamp_list(file);
    ASSERT_TRUE(parsed) << parsed.status().to_string();
    ASSERT_EQ(parsed->entries.size(), 2u);
    EXPECT_EQ(parsed->entries[1].stamp_ns, 1305031102241970000);
    ASSERT_EQ(parsed->errors.size(), 4u);
    EXPECT_EQ(parsed->errors[0].rfind(file + ":2: ", 0), 0u) << parsed->errors[0];
    EXPECT_TRUE(contains(parsed->errors[0], "first stamp (line 1) is in nanoseconds"))
        << parsed->errors[0];
    EXPECT_EQ(parsed->errors[1].rfind(file + ":3: ", 0), 0u) << parsed->errors[1];
    EXPECT_TRUE(contains(parsed->errors[1], "'1e300'")) << parsed->errors[1];
    EXPECT_EQ(parsed->errors[2].rfind(file + ":4: ", 0), 0u) << parsed->errors[2];
    EXPECT_TRUE(contains(parsed->errors[2], "negative")) << parsed->errors[2];
    EXPECT_EQ(parsed->errors[3].rfind(file + ":5: ", 0), 0u) << parsed->errors[3];
    EXPECT_TRUE(contains(parsed->errors[3], "beyond year 2262")) << parsed->errors[3];
}

/// A folder of two 64x48 frames listed in rgb.txt and depth.txt (no associations.txt) with the
/// stamps given as text.
void write_listed_folder(const TempFolder& tmp, const std::vector<std::string>& stamps) {
    std::vector<RgbdImage> frames;
    for (size_t i = 0; i < stamps.size(); ++i) {
        frames.push_back(test::make_frame(1'000'000'000LL * static_cast<int64_t>(i + 1), i));
    }
    ASSERT_TRUE(write_tum_folder(tmp.str(), frames));
    std::filesystem::remove(tmp / "associations.txt");
    std::string rgb, depth;
    for (size_t i = 0; i < stamps.size(); ++i) {
        const std::string name = std::to_string(i + 1) + ".000000.png";
        rgb += stamps[i] + " rgb/" + name + "\n";
        depth += stamps[i] + " depth/" + name + "\n";
    }
    write_file(tmp / "rgb.txt", rgb);
    write_file(tmp / "depth.txt", depth);
}

TEST(TumFolderSourceStamps, IdenticalNanosecondStampsAssociateAndStayExact) {
    TempFolder tmp;
    write_listed_folder(tmp, {"1305031102175304123", "1305031102208637456"});
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    config.use_associations_file = false;
    auto source = TumFolderSource::open(config);
    ASSERT_TRUE(source) << source.status().to_string();
    ASSERT_EQ((*source)->size(), 2);
    const FrameRead first = (*source)->next();
    ASSERT_EQ(first.kind, FrameRead::Kind::kFrame) << first.error;
    EXPECT_EQ(first.image.sensor_ns, 1305031102175304123);
    EXPECT_EQ((*source)->next().image.sensor_ns, 1305031102208637456);
}

TEST(TumFolderSourceStamps, OutOfRangeStampsAreListedNotPublished) {
    TempFolder tmp;
    write_listed_folder(tmp, {"1.0", "1e300"});
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    config.use_associations_file = false;
    auto source = TumFolderSource::open(config);
    ASSERT_TRUE(source) << source.status().to_string();
    EXPECT_EQ((*source)->size(), 1);
    ASSERT_EQ((*source)->list_errors().size(), 2u);  // rgb.txt:2 and depth.txt:2
    EXPECT_TRUE(contains((*source)->list_errors()[0], "rgb.txt:2: time stamp '1e300'"))
        << (*source)->list_errors()[0];
    EXPECT_TRUE(contains((*source)->describe(), "2 malformed lines skipped"))
        << (*source)->describe();
}

TEST(TumFolderSourceStamps, BadWindowIsRefusedAtOpen) {
    TempFolder tmp;
    write_listed_folder(tmp, {"1.0"});
    for (double window : {0.0, -1.0, std::nan(""), 1e300}) {
        TumFolderConfig config;
        config.folder = tmp.str();
        config.intrinsics = test::kSmallIntrinsics;
        config.max_difference_s = window;
        auto source = TumFolderSource::open(config);
        ASSERT_FALSE(source) << window;
        EXPECT_TRUE(contains(source.status().message(), "max_difference_s"))
            << source.status().message();
        EXPECT_TRUE(contains(source.status().message(), "allowed: > 0 and <= 1e6 s"))
            << source.status().message();
    }
}

TEST(TrajectoryStamps, NanosecondTrajectoryIsReadAndBadStampsNamed) {
    TempFolder tmp;
    const std::string file = tmp / "groundtruth.txt";
    write_file(file,
               "1305031102175304123 1 2 3 0 0 0 1\n"
               "1e300 1 2 3 0 0 0 1\n"
               "1305031102.5 1 2 3 0 0 0 1\n");
    auto read = read_tum_trajectory(file);
    ASSERT_TRUE(read) << read.status().to_string();
    ASSERT_EQ(read->poses.size(), 1u);
    EXPECT_NEAR(read->poses[0].stamp_s, 1305031102.175304123, 1e-6);
    ASSERT_EQ(read->errors.size(), 2u);
    EXPECT_EQ(read->errors[0].rfind(file + ":2: time stamp '1e300'", 0), 0u) << read->errors[0];
    EXPECT_EQ(read->errors[1].rfind(file + ":3: ", 0), 0u) << read->errors[1];
    EXPECT_TRUE(contains(read->errors[1], "in seconds but the file's first stamp"))
        << read->errors[1];
}

TEST(TrajectoryStamps, WritingAStampBeyond2262IsRefused) {
    TempFolder tmp;
    StampedPose pose;
    pose.stamp_s = 1e300;
    const Status s = write_tum_trajectory(tmp / "t.txt", {pose});
    ASSERT_FALSE(s);
    EXPECT_TRUE(contains(s.message(), "[0, 9223372036] s")) << s.message();
}

}  // namespace
}  // namespace df::io
