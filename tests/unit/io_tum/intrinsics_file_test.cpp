// intrinsics.txt: read as df_make_sequence writes it, every value checked, nonsense refused
// naming file, line, field and range.
#include "io/tum/intrinsics_file.hpp"

#include <gtest/gtest.h>

#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::contains;
using test::TempFolder;
using test::write_file;

TEST(IntrinsicsFile, ReadsWhatDfMakeSequenceWrites) {
    TempFolder tmp;
    write_file(tmp / "intrinsics.txt",
               "# fx fy cx cy width height depth_units_per_m\n"
               "535.400000 539.200000 320.100000 247.600000 640 480 5000.0\n");
    auto file = read_intrinsics_file(tmp / "intrinsics.txt");
    ASSERT_TRUE(file) << file.status().message();
    EXPECT_DOUBLE_EQ(file->intrinsics.fx, 535.4);
    EXPECT_DOUBLE_EQ(file->intrinsics.cy, 247.6);
    EXPECT_EQ(file->width, 640);
    EXPECT_EQ(file->height, 480);
    EXPECT_DOUBLE_EQ(file->depth_units_per_m, 5000.0);
}

TEST(IntrinsicsFile, NonsenseValuesAreRefusedNamingLineFieldAndRange) {
    TempFolder tmp;
    const std::string file = tmp / "intrinsics.txt";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"1e-300 535 320 240 640 480 5000", ":2: fx is 1e-300, allowed [32, 12800] for 640x480"},
        {"535 539 1e300 240 640 480 5000", ":2: cx is 1e+300, allowed [0, 640] for 640x480"},
        {"535 nan 320 240 640 480 5000", ":2: expected 'fx fy cx cy width height"},
        {"535 539 320 240 64000 480 5000", ":2: image size 64000x480, allowed: 1x1 to 640x480"},
        {"535 539 320 240 0 0 5000", ":2: image size 0x0"},
        {"53.5 53.9 320.1 247.6 64 48 5000", ":2: cx is 320.1, allowed [0, 64] for 64x48 images"},
        {"535 539 320 240 640 480 -1", ":2: depth_units_per_m is -1, allowed: > 0 and <= 1e6"},
        {"535 539 320 240", ":2: expected 'fx fy cx cy width height depth_units_per_m'"},
    };
    for (const auto& [line, want] : cases) {
        write_file(file, "# fx fy cx cy width height depth_units_per_m\n" + line + "\n");
        auto read = read_intrinsics_file(file);
        ASSERT_FALSE(read) << line;
        EXPECT_EQ(read.status().code(), StatusCode::kInvalidArgument) << line;
        EXPECT_TRUE(contains(read.status().message(), file + want))
            << line << ": " << read.status().message();
    }
}

TEST(IntrinsicsFile, MissingEmptyAndFolder) {
    TempFolder tmp;
    EXPECT_EQ(read_intrinsics_file(tmp / "none.txt").status().code(), StatusCode::kNotFound);
    write_file(tmp / "empty.txt", "# only a comment\n");
    EXPECT_TRUE(
        contains(read_intrinsics_file(tmp / "empty.txt").status().message(), "no intrinsics line"));
    EXPECT_EQ(read_intrinsics_file(tmp.str()).status().code(), StatusCode::kIoError);
}

TEST(TumFolderConfig, TakesTheFolderIntrinsicsFileOverThePreset) {
    TempFolder tmp;
    write_file(tmp / "intrinsics.txt", "300 310 160 120 320 240 1000\n");
    auto config = tum_folder_config(tmp.str(), "fr1");
    ASSERT_TRUE(config) << config.status().message();
    EXPECT_EQ(config->folder, tmp.str());
    EXPECT_DOUBLE_EQ(config->intrinsics.fx, 300);
    EXPECT_DOUBLE_EQ(config->intrinsics.cy, 120);
    EXPECT_EQ(config->width, 320);
    EXPECT_EQ(config->height, 240);
    EXPECT_DOUBLE_EQ(config->depth_units_per_m, 1000);
}

TEST(TumFolderConfig, WithoutAnIntrinsicsFileThePresetHolds) {
    TempFolder tmp;
    auto fr1 = tum_folder_config(tmp.str(), "fr1");
    ASSERT_TRUE(fr1) << fr1.status().message();
    EXPECT_DOUBLE_EQ(fr1->intrinsics.fx, 517.3);
    EXPECT_DOUBLE_EQ(fr1->depth_units_per_m, 5000);
    EXPECT_EQ(fr1->width, 0);  // the first image's size
    auto scenes = tum_folder_config(tmp.str(), "7scenes");
    ASSERT_TRUE(scenes) << scenes.status().message();
    EXPECT_DOUBLE_EQ(scenes->depth_units_per_m, 1000);
    EXPECT_EQ(scenes->depth_invalid_value, 65535);
    EXPECT_TRUE(contains(tum_folder_config(tmp.str(), "fr9").status().message(), "fr9"));
}

TEST(TumFolderConfig, ABadIntrinsicsFileIsAnErrorNotThePreset) {
    TempFolder tmp;
    write_file(tmp / "intrinsics.txt", "300 310 160 120 320 240 -1\n");
    auto config = tum_folder_config(tmp.str());
    ASSERT_FALSE(config);
    EXPECT_TRUE(contains(config.status().message(), "intrinsics.txt:1: depth_units_per_m is -1"));
}

}  // namespace
}  // namespace df::io
