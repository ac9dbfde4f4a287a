// TUM trajectory files: round trip and malformed lines.
#include "io/tum/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tum_test_util.hpp"

namespace df::io {
namespace {

using test::TempFolder;
using test::write_file;

TEST(TumTrajectory, WriteThenReadGivesTheSamePoses) {
    TempFolder tmp;
    std::vector<StampedPose> poses;
    for (int i = 0; i < 50; ++i) {
        StampedPose p;
        p.stamp_s = 1305031102.175304 + i / 30.0;
        p.stamp_s = std::round(p.stamp_s * 1e6) / 1e6;  // the file keeps microseconds
        p.t = Eigen::Vector3d(0.1 * i, -2.0 + std::sin(i), 1e-3 * i * i);
        p.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized()));
        poses.push_back(p);
    }
    const std::string file = tmp / "groundtruth.txt";
    ASSERT_TRUE(write_tum_trajectory(file, poses));
    auto read = read_tum_trajectory(file);
    ASSERT_TRUE(read) << read.status().to_string();
    EXPECT_TRUE(read->errors.empty());
    ASSERT_EQ(read->poses.size(), poses.size());
    for (size_t i = 0; i < poses.size(); ++i) {
        EXPECT_NEAR(read->poses[i].stamp_s, poses[i].stamp_s, 1e-6);
        EXPECT_LT((read->poses[i].t - poses[i].t).norm(), 1e-8) << i;
        EXPECT_LT(read->poses[i].q.angularDistance(poses[i].q), 1e-8) << i;
    }
}

TEST(TumTrajectory, ReadsTumLinesAndNormalisesQuaternions) {
    TempFolder tmp;
    const std::string file = tmp / "traj.txt";
    // A line of TUM's freiburg1_xyz ground truth, and a quaternion off unit length.
    write_file(file,
               "# ground truth trajectory\n"
               "# timestamp tx ty tz qx qy qz qw\n"
               "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"
               "2.0\t0\t0\t0\t0\t0\t0\t2\n");
    auto read = read_tum_trajectory(file);
    ASSERT_TRUE(read) << read.status().to_string();
    ASSERT_EQ(read->poses.size(), 2u);
    EXPECT_DOUBLE_EQ(read->poses[0].stamp_s, 1305031098.6659);
    EXPECT_DOUBLE_EQ(read->poses[0].t.y(), 0.6305);
    EXPECT_NEAR(read->poses[0].q.x(), 0.6132, 1e-3);  // x y z w order in the file
    EXPECT_NEAR(read->poses[0].q.w(), -0.3986, 1e-3);
    EXPECT_DOUBLE_EQ(read->poses[1].q.w(), 1.0);
    EXPECT_NEAR(read->poses[0].q.norm(), 1.0, 1e-12);
}

TEST(TumTrajectory, MalformedLinesNameFileAndLine) {
    TempFolder tmp;
    const std::string file = tmp / "traj.txt";
    write_file(file,
               "1.0 0 0 0 0 0 0 1\n"
               "2.0 0 0 0 0 0 0\n"
               "x 0 0 0 0 0 0 1\n"
               "4.0 0 abc 0 0 0 0 1\n"
               "5.0 0 0 0 0 0 0 0\n"
               "-6.0 0 0 0 0 0 0 1\n"
               "7.0 0 0 nan 0 0 0 1\n"
               "8.0 0 0 0 0 0 0 1\n");
    auto read = read_tum_trajectory(file);
    ASSERT_TRUE(read) << read.status().to_string();
    ASSERT_EQ(read->poses.size(), 2u);
    EXPECT_DOUBLE_EQ(read->poses[1].stamp_s, 8.0);
    ASSERT_EQ(read->errors.size(), 6u);
    for (int i = 0; i < 6; ++i) {
        const std::string prefix = file + ":" + std::to_string(i + 2) + ": ";
        EXPECT_EQ(read->errors[i].rfind(prefix, 0), 0u) << read->errors[i];
    }
    EXPECT_NE(read->errors[0].find("found 7 fields"), std::string::npos) << read->errors[0];
    EXPECT_NE(read->errors[2].find("ty"), std::string::npos) << read->errors[2];
    EXPECT_NE(read->errors[3].find("quaternion"), std::string::npos) << read->errors[3];
}

TEST(TumTrajectory, MissingFileAndUnwritableFileAreErrors) {
    TempFolder tmp;
    auto read = read_tum_trajectory(tmp / "missing.txt");
    ASSERT_FALSE(read);
    EXPECT_EQ(read.status().code(), StatusCode::kNotFound);
    EXPECT_NE(read.status().message().find(tmp / "missing.txt"), std::string::npos);

    const Status status = write_tum_trajectory(tmp / "no/such/folder/traj.txt", {StampedPose{}});
    EXPECT_EQ(status.code(), StatusCode::kIoError);
    EXPECT_NE(status.message().find("traj.txt"), std::string::npos);

    StampedPose bad;
    bad.t.x() = std::nan("");
    EXPECT_EQ(write_tum_trajectory(tmp / "traj.txt", {bad}).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace df::io
