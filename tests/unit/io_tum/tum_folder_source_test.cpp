// TumFolderSource on good folders: round trips through write_tum_folder, list choice, open errors.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io/tum/tum_folder.hpp"
#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::make_frame;
using test::same_pixels;
using test::TempFolder;
using test::contains;
using test::write_file;

std::vector<RgbdImage> make_frames(int count) {
    std::vector<RgbdImage> frames;
    for (int i = 0; i < count; ++i) {
        frames.push_back(make_frame(1'305'031'102'000'000'000 + i * 33'333'000LL, i));
    }
    return frames;
}

std::unique_ptr<TumFolderSource> open_ok(const TumFolderConfig& config) {
    auto source = TumFolderSource::open(config);
    EXPECT_TRUE(source) << source.status().to_string();
    return source ? std::move(source).value() : nullptr;
}

TEST(TumFolderSource, RoundTripIsByteIdentical) {
    TempFolder tmp;
    const auto frames = make_frames(5);
    ASSERT_TRUE(write_tum_folder(tmp.str(), frames));

    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = Intrinsics{51.73, 51.65, 31.86, 25.53};  // fr1 for 64x48
    auto source = open_ok(config);
    ASSERT_TRUE(source);
    EXPECT_EQ(source->size(), 5);
    EXPECT_EQ(source->describe(), "TUM folder " + tmp.str() + " (5 frames, associations.txt)");
    EXPECT_TRUE(source->list_errors().empty());
    for (int i = 0; i < 5; ++i) {
        const FrameRead read = source->next();
        ASSERT_EQ(read.kind, FrameRead::Kind::kFrame) << read.error;
        const RgbdImage& image = read.image;
        EXPECT_TRUE(same_pixels(image.rgb, frames[i].rgb)) << "frame " << i;
        EXPECT_TRUE(same_pixels(image.depth, frames[i].depth)) << "frame " << i;
        // Stamps travel as text with microseconds; these are whole microseconds, read exactly.
        EXPECT_EQ(image.sensor_ns, frames[i].sensor_ns);
        EXPECT_EQ(image.index, static_cast<uint64_t>(i));
        EXPECT_DOUBLE_EQ(image.intrinsics.fx, 51.73);
        EXPECT_DOUBLE_EQ(image.depth_units_per_m, 5000.0);
        EXPECT_TRUE(std::filesystem::exists(image.rgb_path)) << image.rgb_path;
        EXPECT_TRUE(contains(image.depth_path, "depth/")) << image.depth_path;
    }
    EXPECT_EQ(source->next().kind, FrameRead::Kind::kEnd);
    EXPECT_EQ(source->next().kind, FrameRead::Kind::kEnd);
    source->rewind();
    EXPECT_EQ(source->next().kind, FrameRead::Kind::kFrame);
}

TEST(TumFolderSource, SmallStampsRoundTripExactly) {
    TempFolder tmp;
    std::vector<RgbdImage> frames = {make_frame(1'033'333'000, 1), make_frame(1'000'000, 2)};
    ASSERT_TRUE(write_tum_folder(tmp.str(), frames));
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    auto source = open_ok(config);
    ASSERT_TRUE(source);
    // Frames come in stamp order whatever order they were written in.
    EXPECT_EQ(source->next().image.sensor_ns, 1'000'000);
    EXPECT_EQ(source->next().image.sensor_ns, 1'033'333'000);
}

TEST(TumFolderSource, AssociatesRgbAndDepthListsWhenNoAssociationsFile) {
    TempFolder tmp;
    ASSERT_TRUE(write_tum_folder(tmp.str(), make_frames(3)));
    // An associations.txt naming only one pair: ignored when use_associations_file is false.
    write_file(tmp / "associations.txt",
               "1305031102.000000 rgb/1305031102.000000.png 1305031102.000000 "
               "depth/1305031102.000000.png\n");
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    EXPECT_EQ(open_ok(config)->size(), 1);

    config.use_associations_file = false;
    auto source = open_ok(config);
    ASSERT_TRUE(source);
    EXPECT_EQ(source->size(), 3);
    EXPECT_TRUE(contains(source->describe(), "rgb.txt + depth.txt")) << source->describe();

    std::filesystem::remove(tmp / "associations.txt");
    config.use_associations_file = true;
    source = open_ok(config);
    ASSERT_TRUE(source);
    EXPECT_EQ(source->size(), 3);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(source->next().kind, FrameRead::Kind::kFrame);
    EXPECT_EQ(source->next().kind, FrameRead::Kind::kEnd);
}

TEST(TumFolderSource, DepthInvalidValueBecomesZero) {
    TempFolder tmp;
    std::vector<RgbdImage> frames = make_frames(1);
    cv::Mat& depth = frames[0].depth;
    depth.at<uint16_t>(0, 0) = 65535;
    depth.at<uint16_t>(0, 1) = 65534;
    depth.at<uint16_t>(0, 2) = 1000;
    ASSERT_TRUE(write_tum_folder(tmp.str(), frames));

    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    cv::Mat read = open_ok(config)->next().image.depth;  // default: nothing is invalid
    EXPECT_EQ(read.at<uint16_t>(0, 0), 65535);

    config.depth_invalid_value = 65535;
    config.depth_units_per_m = 1000;
    const FrameRead frame = open_ok(config)->next();
    ASSERT_EQ(frame.kind, FrameRead::Kind::kFrame) << frame.error;
    EXPECT_EQ(frame.image.depth.at<uint16_t>(0, 0), 0);
    EXPECT_EQ(frame.image.depth.at<uint16_t>(0, 1), 65534);
    EXPECT_EQ(frame.image.depth.at<uint16_t>(0, 2), 1000);
    EXPECT_DOUBLE_EQ(frame.image.depth_units_per_m, 1000.0);
    cv::Mat expected = depth.clone();
    expected.at<uint16_t>(0, 0) = 0;
    EXPECT_TRUE(same_pixels(frame.image.depth, expected));
}

TEST(TumFolderSource, MalformedListLinesAreSkippedAndListed) {
    TempFolder tmp;
    ASSERT_TRUE(write_tum_folder(tmp.str(), make_frames(2)));
    std::filesystem::remove(tmp / "associations.txt");
    write_file(tmp / "rgb.txt",
               "# color images\n"
               "1305031102.000000 rgb/1305031102.000000.png\n"
               "oops rgb/nothing.png\n"
               "1305031102.033333 rgb/1305031102.033333.png\n"
               "1305031102.5\n");
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    auto source = open_ok(config);
    ASSERT_TRUE(source);
    EXPECT_EQ(source->size(), 2);
    ASSERT_EQ(source->list_errors().size(), 2u);
    EXPECT_TRUE(contains(source->list_errors()[0], tmp / "rgb.txt" + ":3: "))
        << source->list_errors()[0];
    EXPECT_TRUE(contains(source->list_errors()[1], tmp / "rgb.txt" + ":5: "))
        << source->list_errors()[1];
    EXPECT_TRUE(contains(source->describe(), "2 malformed lines")) << source->describe();
}

TEST(TumFolderSourceOpen, MissingFolderSaysWhatWasExpected) {
    TempFolder tmp;
    TumFolderConfig config;
    config.folder = tmp / "no_such_folder";
    auto source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    const std::string& message = source.status().message();
    EXPECT_TRUE(contains(message, config.folder)) << message;
    EXPECT_TRUE(contains(message, "does not exist")) << message;
    EXPECT_TRUE(contains(message, "rgb.txt")) << message;
}

TEST(TumFolderSourceOpen, FileInsteadOfFolder) {
    TempFolder tmp;
    write_file(tmp / "file.txt", "hello\n");
    TumFolderConfig config;
    config.folder = tmp / "file.txt";
    auto source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    EXPECT_TRUE(contains(source.status().message(), "is not a folder"))
        << source.status().message();
}

TEST(TumFolderSourceOpen, UnreadableFolder) {
    if (::geteuid() == 0) GTEST_SKIP() << "root can read any folder";
    TempFolder tmp;
    const std::string folder = tmp / "locked";
    std::filesystem::create_directories(folder);
    ASSERT_EQ(::chmod(folder.c_str(), 0), 0);
    TumFolderConfig config;
    config.folder = folder;
    auto source = TumFolderSource::open(config);
    ::chmod(folder.c_str(), 0700);
    ASSERT_FALSE(source);
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    EXPECT_TRUE(contains(source.status().message(), folder)) << source.status().message();
}

TEST(TumFolderSourceOpen, MissingRgbOrDepthList) {
    TempFolder tmp;
    ASSERT_TRUE(write_tum_folder(tmp.str(), make_frames(2)));
    std::filesystem::remove(tmp / "associations.txt");
    std::filesystem::remove(tmp / "rgb.txt");
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    auto source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_EQ(source.status().code(), StatusCode::kNotFound);
    EXPECT_TRUE(contains(source.status().message(), "has no rgb.txt")) << source.status().message();
    EXPECT_TRUE(contains(source.status().message(), "associations.txt"))
        << source.status().message();

    ASSERT_TRUE(write_tum_folder(tmp.str(), make_frames(2)));
    std::filesystem::remove(tmp / "associations.txt");
    std::filesystem::remove(tmp / "depth.txt");
    source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_TRUE(contains(source.status().message(), "has no depth.txt"))
        << source.status().message();
}

TEST(TumFolderSourceOpen, NoPairsIsAnError) {
    TempFolder tmp;
    write_file(tmp / "rgb.txt", "1.0 rgb/1.png\n2.0 rgb/2.png\n");
    write_file(tmp / "depth.txt", "1.5 depth/1.png\n");
    TumFolderConfig config;
    config.folder = tmp.str();
    config.intrinsics = test::kSmallIntrinsics;
    auto source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_TRUE(contains(source.status().message(), "no frames")) << source.status().message();
    EXPECT_TRUE(contains(source.status().message(), "0.02 s")) << source.status().message();

    write_file(tmp / "associations.txt", "# only a comment\n1.0 rgb/1.png\n");
    source = TumFolderSource::open(config);
    ASSERT_FALSE(source);
    EXPECT_TRUE(contains(source.status().message(), "associations.txt:2"))
        << source.status().message();
}

TEST(WriteTumFolder, RejectsBadFramesWithoutWriting) {
    TempFolder tmp;
    auto frames = make_frames(3);
    frames[2].depth.convertTo(frames[2].depth, CV_32F);
    Status status = write_tum_folder(tmp / "out", frames);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(contains(status.message(), "frame 2")) << status.message();
    EXPECT_FALSE(std::filesystem::exists(tmp / "out"));

    frames = make_frames(3);
    frames[1].sensor_ns = frames[0].sensor_ns + 100;  // same microsecond, same file name
    status = write_tum_folder(tmp / "out", frames);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(contains(status.message(), "same stamp")) << status.message();
}

TEST(WriteTumFolder, WritesNamedFilesAndSortedLists) {
    TempFolder tmp;
    std::vector<RgbdImage> frames = {make_frame(2'500'000'000, 1), make_frame(1'250'000'000, 2)};
    ASSERT_TRUE(write_tum_folder(tmp.str(), frames));
    EXPECT_TRUE(std::filesystem::exists(tmp / "rgb/1.250000.png"));
    EXPECT_TRUE(std::filesystem::exists(tmp / "depth/2.500000.png"));
    auto rgb = parse_stamp_list(tmp / "rgb.txt");
    ASSERT_TRUE(rgb);
    ASSERT_EQ(rgb->entries.size(), 2u);
    EXPECT_EQ(rgb->entries[0].path, "rgb/1.250000.png");
    EXPECT_EQ(rgb->entries[1].path, "rgb/2.500000.png");
    auto associations = parse_associations(tmp / "associations.txt");
    ASSERT_TRUE(associations);
    ASSERT_EQ(associations->pairs.size(), 2u);
    EXPECT_EQ(associations->pairs[1].depth.path, "depth/2.500000.png");
    // PNG on disk holds B,G,R: the written colour matches the frame's R,G,B after conversion.
    cv::Mat bgr = cv::imread(tmp / "rgb/2.500000.png", cv::IMREAD_UNCHANGED);
    ASSERT_EQ(bgr.type(), CV_8UC3);
    EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0)[0], frames[0].rgb.at<cv::Vec3b>(0, 0)[2]);
}

}  // namespace
}  // namespace df::io
