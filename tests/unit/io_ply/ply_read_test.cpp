// Reading hand-made PLY files: ASCII and binary, every scalar type, elements around the
// vertices, and malformed files whose errors must name the file and the problem.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "io/ply/ply.hpp"
#include "ply_test_util.hpp"

namespace df::io {
namespace {

using test::put;
using test::TempFolder;
using test::write_file;

TEST(PlyRead, AsciiWithCrLfCommentsNormalsColoursAndFaces) {
    TempFolder tmp;
    const std::string file = tmp / "a.ply";
    write_file(file,
               "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 3\r\n"
               "property float x\r\nproperty float y\r\nproperty float z\r\n"
               "property float nx\r\nproperty float ny\r\nproperty float nz\r\n"
               "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
               "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
               "0.5 1.5 -2 0 0 1 255 0 0\r\n1 2 3 0 0 1 0 255 0\r\n-1e-3 0 7.25 0 1 0 0 0 255\r\n"
               "3 0 1 2\r\n");
    PlyReadInfo info;
    auto ply = read_ply(file, &info);
    ASSERT_TRUE(ply) << ply.status().to_string();
    ASSERT_EQ(ply->size(), 3u);
    EXPECT_EQ(ply->positions[0], Eigen::Vector3d(0.5, 1.5, -2));
    EXPECT_EQ(ply->positions[2], Eigen::Vector3d(-1e-3, 0, 7.25));
    ASSERT_EQ(ply->normals.size(), 3u);
    EXPECT_EQ(ply->normals[2], Eigen::Vector3f(0, 1, 0));
    ASSERT_EQ(ply->colours.size(), 3u);
    EXPECT_EQ(ply->colours[0], Rgb8(255, 0, 0));
    EXPECT_EQ(ply->colours[2], Rgb8(0, 0, 255));
    EXPECT_TRUE(ply->scalars.empty());
    EXPECT_EQ(info.format, PlyFormat::kAscii);
    ASSERT_EQ(info.comments.size(), 1u);
    EXPECT_EQ(info.comments[0], "made by hand");
}

TEST(PlyRead, AsciiPositionsOnlyWithFacesAfterAndBlankLines) {
    TempFolder tmp;
    const std::string file = tmp / "b.ply";
    write_file(file,
               "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
               "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
               "end_header\n1 2 3\n\n4 5 6\n");
    auto ply = read_ply(file);
    ASSERT_TRUE(ply) << ply.status().to_string();
    ASSERT_EQ(ply->size(), 2u);
    EXPECT_EQ(ply->positions[1], Eigen::Vector3d(4, 5, 6));
    EXPECT_FALSE(ply->has_normals());
    EXPECT_FALSE(ply->has_colours());
}

TEST(PlyRead, BinaryDoubleWithAFaceElementFirstAndAnIncompleteColour) {
    TempFolder tmp;
    const std::string file = tmp / "b.ply";
    std::string data =
        "ply\nformat binary_little_endian 1.0\nelement face 1\n"
        "property list uchar int vertex_indices\nelement vertex 2\nproperty double x\n"
        "property uchar red\nproperty double y\nproperty double z\nend_header\n";
    put<uint8_t>(&data, 3);
    for (int32_t i : {0, 1, 1}) put(&data, i);
    const double v[2][3] = {{1.5, -2.5, 3.5}, {4, 5, 6}};
    for (const auto& p : v) {
        put(&data, p[0]);
        put<uint8_t>(&data, 200);
        put(&data, p[1]);
        put(&data, p[2]);
    }
    write_file(file, data);
    PlyReadInfo info;
    auto ply = read_ply(file, &info);
    ASSERT_TRUE(ply) << ply.status().to_string();
    ASSERT_EQ(ply->size(), 2u);
    EXPECT_EQ(ply->positions[0], Eigen::Vector3d(1.5, -2.5, 3.5));
    EXPECT_EQ(ply->positions[1], Eigen::Vector3d(4, 5, 6));
    EXPECT_EQ(info.format, PlyFormat::kBinaryLittleEndian);
    // red without green and blue is no colour, but an extra property.
    EXPECT_FALSE(ply->has_colours());
    ASSERT_NE(ply->scalar("red"), nullptr);
    EXPECT_EQ(*ply->scalar("red"), std::vector<float>({200, 200}));
}

TEST(PlyRead, BinaryIntegerTypesListsInVerticesAndExtraProperties) {
    TempFolder tmp;
    const std::string file = tmp / "i.ply";
    std::string data =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty int16 x\n"
        "property int y\nproperty uint8 z\nproperty list uint8 float32 weights\n"
        "property ushort green\nproperty uint16 red\nproperty char blue\n"
        "property double confidence\nproperty float32 nx\nproperty float32 ny\n"
        "property float32 nz\nend_header\n";
    for (int k = 0; k < 2; ++k) {
        put<int16_t>(&data, static_cast<int16_t>(-3 + k));
        put<int32_t>(&data, 100000 * (k + 1));
        put<uint8_t>(&data, 250);
        put<uint8_t>(&data, static_cast<uint8_t>(k + 1));  // list of k + 1 floats, skipped
        for (int j = 0; j <= k; ++j) put<float>(&data, 9.f);
        put<uint16_t>(&data, 300);  // green above 255: clamped
        put<uint16_t>(&data, 17);
        put<int8_t>(&data, -5);  // blue below 0: clamped
        put<double>(&data, 0.25 * k);
        for (float n : {0.f, 0.f, -1.f}) put(&data, n);
    }
    write_file(file, data);
    auto ply = read_ply(file);
    ASSERT_TRUE(ply) << ply.status().to_string();
    ASSERT_EQ(ply->size(), 2u);
    EXPECT_EQ(ply->positions[0], Eigen::Vector3d(-3, 100000, 250));
    EXPECT_EQ(ply->positions[1], Eigen::Vector3d(-2, 200000, 250));
    ASSERT_TRUE(ply->has_colours());
    EXPECT_EQ(ply->colours[1], Rgb8(17, 255, 0));
    ASSERT_TRUE(ply->has_normals());
    EXPECT_EQ(ply->normals[1], Eigen::Vector3f(0, 0, -1));
    ASSERT_EQ(ply->scalars.size(), 1u);
    EXPECT_EQ(ply->scalars[0].name, "confidence");
    EXPECT_EQ(ply->scalars[0].values, std::vector<float>({0.f, 0.25f}));
}

TEST(PlyRead, NonFiniteVerticesAreDroppedWithAllTheirProperties) {
    TempFolder tmp;
    const std::string file = tmp / "nan.ply";
    write_file(file,
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nproperty float radius\nend_header\n"
               "1 2 3 0.1\nnan 0 0 0.2\n4 inf 6 0.3\n");
    PlyReadInfo info;
    auto ply = read_ply(file, &info);
    ASSERT_TRUE(ply) << ply.status().to_string();
    ASSERT_EQ(ply->size(), 1u);
    EXPECT_EQ(info.skipped_nonfinite, 2u);
    EXPECT_EQ(*ply->scalar("radius"), std::vector<float>({0.1f}));
}

TEST(PlyRead, MalformedFilesNameTheFileAndTheProblem) {
    TempFolder tmp;
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n";
    const std::string binary_header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n";
    struct Case {
        std::string name, text, expected;
    } cases[] = {
        {"not_ply.ply", "PLY?\n", "not a PLY file"},
        {"big.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n",
         "big_endian"},
        {"odd_format.ply", "ply\nformat text 1.0\nelement vertex 0\nend_header\n",
         "unknown PLY format 'text'"},
        {"no_format.ply", "ply\nelement vertex 0\nend_header\n", "no 'format' line"},
        {"no_vertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n",
         "no 'element vertex'"},
        {"no_z.ply",
         "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
         "property float y\nend_header\n1 2\n",
         "lacks a property x, y or z"},
        {"list_x.ply",
         "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
         "property float y\nproperty float z\nend_header\n1 1 2 3\n",
         "'x' is a list"},
        {"no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", "end_header"},
        {"bad_element.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n",
         "bad_element.ply:3: expected 'element <name> <count>'"},
        {"orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
         "property before any element"},
        {"junk.ply", "ply\nformat ascii 1.0\nelement vertex 0\nhello\nend_header\n",
         "unexpected header line 'hello'"},
        {"short.ply", header + "1 2 3\n", "ends after 1 of 2"},
        {"bad_number.ply", header + "1 2 3\n4 abc 6\n",
         "bad_number.ply:9: vertex 1: expected a number for y, found 'abc'"},
        {"few_values.ply", header + "1 2 3\n4 5\n", "expected 3 values, found 2"},
        {"bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\n", ":4:"},
        {"bad_list.ply",
         "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar real v\n"
         "end_header\n",
         "expected 'property list <count type> <item type> <name>'"},
        {"truncated.ply", binary_header + std::string(12, '\0') + "abc",
         "ends inside element 'vertex' 1 of 2"},
        {"truncated_faces.ply",
         "ply\nformat binary_little_endian 1.0\nelement face 3\nproperty int a\n"
         "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n" +
             std::string(9, '\0'),
         "ends inside element 'face' 2 of 3"},
    };
    for (const Case& c : cases) {
        const std::string file = tmp / c.name;
        write_file(file, c.text);
        auto ply = read_ply(file);
        ASSERT_FALSE(ply) << c.name;
        EXPECT_NE(ply.status().message().find(file), std::string::npos) << ply.status().message();
        EXPECT_NE(ply.status().message().find(c.expected), std::string::npos)
            << c.name << ": " << ply.status().message();
    }
    auto missing = read_ply(tmp / "missing.ply");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
    EXPECT_NE(missing.status().message().find("missing.ply"), std::string::npos);
}

TEST(PlyRead, AHugeAnnouncedCountIsATruncationNotAnAllocation) {
    TempFolder tmp;
    const std::string file = tmp / "huge.ply";
    write_file(file,
               "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000000\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n" +
                   std::string(24, '\0'));
    auto ply = read_ply(file);
    ASSERT_FALSE(ply);
    EXPECT_EQ(ply.status().code(), StatusCode::kIoError);
    EXPECT_NE(ply.status().message().find("2 of 4000000000000"), std::string::npos)
        << ply.status().message();
}

}  // namespace
}  // namespace df::io
