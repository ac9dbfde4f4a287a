// Writing clouds and reading them back: everything a cloud holds survives both formats, the
// generator's binary layout is exact to the byte, and inconsistent clouds are refused.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "io/ply/ply.hpp"
#include "ply_test_util.hpp"

namespace df::io {
namespace {

using test::read_file;
using test::TempFolder;

/// Five points with normals, colours and two extra properties, like a SLAM map's surfels.
PointCloud surfels() {
    PointCloud c;
    for (int i = 0; i < 5; ++i) {
        c.positions.emplace_back(0.1 * i, -4 + 1.0 / 3 * i, 1e3 + 0.7 * i);
        c.normals.push_back(Eigen::Vector3f(0.6f, -0.8f * (i % 2 ? 1 : -1), 0).normalized());
        c.colours.emplace_back(static_cast<uint8_t>(50 * i), static_cast<uint8_t>(255 - i),
                               static_cast<uint8_t>(7));
        c.add_scalar("radius").push_back(0.004f * static_cast<float>(i + 1));
        c.add_scalar("confidence").push_back(i == 2 ? 1e-7f : 3.5f * static_cast<float>(i));
    }
    return c;
}

TEST(PlyWrite, EverythingSurvivesBothFormatsAndBothPositionTypes) {
    TempFolder tmp;
    const PointCloud cloud = surfels();
    ASSERT_TRUE(cloud.check());
    for (const PlyFormat format : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
        for (const bool double_positions : {false, true}) {
            SCOPED_TRACE(std::string(format == PlyFormat::kAscii ? "ascii" : "binary") +
                         (double_positions ? " double" : " float"));
            PlyWriteOptions options;
            options.format = format;
            options.double_positions = double_positions;
            options.comments = {"surfels, world frame, metres", "second comment"};
            const std::string file = tmp / "surfels.ply";
            ASSERT_TRUE(write_ply(file, cloud, options));
            PlyReadInfo info;
            auto back = read_ply(file, &info);
            ASSERT_TRUE(back) << back.status().to_string();
            EXPECT_EQ(info.format, format);
            EXPECT_EQ(info.comments, options.comments);
            ASSERT_EQ(back->size(), cloud.size());
            for (size_t i = 0; i < cloud.size(); ++i) {
                const Eigen::Vector3d& p = cloud.positions[i];
                if (double_positions) {
                    EXPECT_EQ(back->positions[i], p);
                } else {
                    EXPECT_LT((back->positions[i] - p.cast<float>().cast<double>()).norm(),
                              1e-6 * p.norm());
                }
            }
            EXPECT_EQ(back->normals, cloud.normals);
            EXPECT_EQ(back->colours, cloud.colours);
            ASSERT_EQ(back->scalars.size(), 2u);
            EXPECT_EQ(back->scalars[0].name, "radius");
            EXPECT_EQ(back->scalars[1].name, "confidence");
            EXPECT_EQ(*back->scalar("radius"), *cloud.scalar("radius"));
            EXPECT_EQ(*back->scalar("confidence"), *cloud.scalar("confidence"));
        }
    }
}

TEST(PlyWrite, PositionsOnlyFloatAndDoubleRoundTrip) {
    TempFolder tmp;
    PointCloud cloud;
    cloud.positions = {{0.1, 0.2, 0.3}, {-4, 5.5, 1e3}, {0, 0, 0}};
    for (const bool double_positions : {false, true}) {
        for (const PlyFormat format : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
            const std::string file = tmp / "p.ply";
            PlyWriteOptions options;
            options.format = format;
            options.double_positions = double_positions;
            ASSERT_TRUE(write_ply(file, cloud, options));
            auto ply = read_ply(file);
            ASSERT_TRUE(ply) << ply.status().to_string();
            ASSERT_EQ(ply->size(), cloud.size());
            EXPECT_FALSE(ply->has_normals() || ply->has_colours() || !ply->scalars.empty());
            for (size_t i = 0; i < cloud.size(); ++i) {
                EXPECT_LT((ply->positions[i] - cloud.positions[i]).norm(),
                          double_positions ? 1e-12 : 1e-4);
            }
        }
    }
}

TEST(PlyWrite, GeneratorModelLayoutIsExactToTheByte) {
    TempFolder tmp;
    PointCloud cloud;
    cloud.positions = {{1.5, -2.25, 3}, {0, 0, 0}};
    cloud.normals = {{0, 1, 0}, {0, 0, 1}};
    cloud.colours = {{200, 100, 7}, {0, 0, 0}};
    PlyWriteOptions options;
    options.comments = {"static scene surface, world frame, metres (df_make_sequence)"};
    const std::string file = tmp / "model.ply";
    ASSERT_TRUE(write_ply(file, cloud, options));
    std::string expected =
        "ply\nformat binary_little_endian 1.0\n"
        "comment static scene surface, world frame, metres (df_make_sequence)\n"
        "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    const float values[2][6] = {{1.5f, -2.25f, 3, 0, 1, 0}, {0, 0, 0, 0, 0, 1}};
    const unsigned char rgb[2][3] = {{200, 100, 7}, {0, 0, 0}};
    for (int i = 0; i < 2; ++i) {
        expected.append(reinterpret_cast<const char*>(values[i]), 24);
        expected.append(reinterpret_cast<const char*>(rgb[i]), 3);
    }
    EXPECT_EQ(read_file(file), expected);
}

TEST(PlyWrite, EmptyCloudRoundTrips) {
    TempFolder tmp;
    for (const PlyFormat format : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
        PlyWriteOptions options;
        options.format = format;
        ASSERT_TRUE(write_ply(tmp / "empty.ply", PointCloud{}, options));
        auto back = read_ply(tmp / "empty.ply");
        ASSERT_TRUE(back) << back.status().to_string();
        EXPECT_TRUE(back->empty());
    }
}

TEST(PlyWrite, InconsistentCloudsAndBadCommentsAreRefused) {
    TempFolder tmp;
    const std::string file = tmp / "bad.ply";
    struct Case {
        std::string what;
        PointCloud cloud;
        std::string expected;
    };
    std::vector<Case> cases;
    cases.push_back({"normals", surfels(), "normals has 4 values for 5 points"});
    cases.back().cloud.normals.pop_back();
    cases.push_back({"colours", surfels(), "colours has 6 values for 5 points"});
    cases.back().cloud.colours.emplace_back(1, 2, 3);
    cases.push_back({"scalar", surfels(), "'radius' has 0 values"});
    cases.back().cloud.scalar("radius")->clear();
    cases.push_back({"reserved", surfels(), "'nx' clashes"});
    cases.back().cloud.scalars.push_back({"nx", std::vector<float>(5)});
    cases.push_back({"twice", surfels(), "'radius' appears twice"});
    cases.back().cloud.scalars.push_back({"radius", std::vector<float>(5)});
    cases.push_back({"space", surfels(), "'my radius' is empty or has white space"});
    cases.back().cloud.scalars.push_back({"my radius", std::vector<float>(5)});
    for (const Case& c : cases) {
        const Status s = write_ply(file, c.cloud);
        ASSERT_FALSE(s) << c.what;
        EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << c.what;
        EXPECT_NE(s.message().find(file), std::string::npos) << s.message();
        EXPECT_NE(s.message().find(c.expected), std::string::npos) << c.what << ": " << s.message();
        EXPECT_FALSE(std::filesystem::exists(file)) << c.what;
    }
    PlyWriteOptions options;
    options.comments = {"two\nlines"};
    const Status comment = write_ply(file, surfels(), options);
    EXPECT_EQ(comment.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(comment.message().find("line break"), std::string::npos) << comment.message();
    const Status unwritable = write_ply(tmp / "no/such/folder/x.ply", surfels());
    EXPECT_EQ(unwritable.code(), StatusCode::kIoError);
    EXPECT_NE(unwritable.message().find("no/such/folder/x.ply"), std::string::npos);
}

TEST(PlyWrite, ScalarAccessors) {
    PointCloud cloud;
    EXPECT_EQ(cloud.scalar("radius"), nullptr);
    std::vector<float>& radius = cloud.add_scalar("radius");
    radius.push_back(1);
    EXPECT_EQ(&cloud.add_scalar("radius"), cloud.scalar("radius"));
    EXPECT_EQ(cloud.scalars.size(), 1u);
    const PointCloud& view = cloud;
    ASSERT_NE(view.scalar("radius"), nullptr);
    EXPECT_EQ(view.scalar("radius")->size(), 1u);
}

}  // namespace
}  // namespace df::io
