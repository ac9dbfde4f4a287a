// The df_eval executable: `run` on a small complete sequence, and the messages of bad inputs.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "eval_test_support.hpp"
#include "io/ply/ply.hpp"
#include "io/tum/trajectory.hpp"

namespace df::eval {
namespace {

using nlohmann::json;
using test::run_command;
using test::TempFolder;
using test::write_file;

Trajectory moved(const Eigen::Isometry3d& T, const Trajectory& t) {
    Trajectory out;
    for (const auto& p : t) out.push_back(test::transformed(T, p));
    return out;
}

/// A sequence (ground truth of camera, one object, the static scene and instance masks) and a
/// run that got everything right in its own world frame.
void make_sequence_and_run(const TempFolder& seq, const TempFolder& run) {
    const Trajectory camera = test::smooth_trajectory(50.0, 30.0, 90);
    Trajectory car;
    for (const auto& p : camera) {
        io::StampedPose c = p;
        c.t = Eigen::Vector3d(2.0 + 0.3 * (p.stamp_s - 50.0), 0.5, 0.0);
        car.push_back(c);
    }
    std::vector<Eigen::Vector3d> scene;
    for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j <= 40; ++j) {
            scene.emplace_back(-1 + 0.05 * i, -1 + 0.05 * j, -0.5);   // floor
            scene.emplace_back(-1 + 0.05 * i, 1.0, -0.5 + 0.05 * j);  // wall
        }
    }
    ASSERT_TRUE(io::write_tum_trajectory(seq / "groundtruth.txt", camera));
    std::filesystem::create_directories(seq / "objects");
    std::filesystem::create_directories(seq / "models");
    std::filesystem::create_directories(seq / "instances");
    ASSERT_TRUE(io::write_tum_trajectory(seq / "objects/car_1.txt", car));
    io::PointCloud scene_cloud;
    scene_cloud.positions = scene;
    ASSERT_TRUE(io::write_ply(seq / "models/static.ply", scene_cloud));
    write_file(seq / "instances.json",
               R"({"instances": [{"id": 1, "name": "car_1", "class_id": 2, "class_name": "car",
                   "kind": "rigid", "model": null, "trajectory": "objects/car_1.txt"}]})");

    const Eigen::Isometry3d est_T_gt =
        test::make_transform(1.1, Eigen::Vector3d(0.2, 1, 0.3), Eigen::Vector3d(0.4, -1, 2));
    ASSERT_TRUE(io::write_tum_trajectory(run / "trajectory.txt", moved(est_T_gt, camera)));
    std::filesystem::create_directories(run / "objects");
    std::filesystem::create_directories(run / "masks");
    ASSERT_TRUE(io::write_tum_trajectory(run / "objects/car_1.txt", moved(est_T_gt, car)));
    io::PointCloud map;
    for (const auto& p : scene) map.positions.push_back(est_T_gt * p);
    io::PlyWriteOptions ascii_double;
    ascii_double.format = io::PlyFormat::kAscii;
    ascii_double.double_positions = true;
    ASSERT_TRUE(io::write_ply(run / "map.ply", map, ascii_double));
    std::string log;
    for (int i = 0; i < 5; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "%.6f.png", camera[static_cast<size_t>(i)].stamp_s);
        cv::Mat gt(24, 32, CV_16UC1, cv::Scalar(0));
        gt(cv::Rect(4 + i, 4, 10, 8)).setTo(1);
        ASSERT_TRUE(cv::imwrite(seq / (std::string("instances/") + name), gt));
        cv::Mat pred = gt * 7;  // any label works
        ASSERT_TRUE(cv::imwrite(run / (std::string("masks/") + name), pred));
        log += "2026-01-01T00:00:00.000 [info] slam: timing seq=" + std::to_string(i) +
               " stage=slam tracking=" + std::to_string(10 + i) + " fusion=4\n";
    }
    write_file(run / "slam.log", log);
}

TEST(DfEvalRun, ScoresEverythingARunFolderHolds) {
    TempFolder seq, run;
    make_sequence_and_run(seq, run);
    std::string out;
    ASSERT_EQ(run_command(std::string(DF_EVAL_BIN) + " run " + seq.str() + " " + run.str(), &out),
              0)
        << out;
    const json doc = test::read_json(run / "eval.json");
    ASSERT_TRUE(doc.is_object()) << out;
    EXPECT_TRUE(doc["errors"].empty()) << doc["errors"];
    EXPECT_LT(doc["camera"]["ate"]["translation_m"]["rmse"].get<double>(), 1e-6);
    EXPECT_EQ(doc["camera"]["ate"]["pairs"], 90);
    EXPECT_LT(doc["camera"]["rpe_1s"]["translation_m"]["max"].get<double>(), 1e-6);
    EXPECT_LT(doc["camera"]["rpe_1f"]["rotation_deg"]["max"].get<double>(), 1e-4);
    EXPECT_LT(doc["objects"]["car_1"]["ate"]["translation_m"]["max"].get<double>(), 1e-6);
    EXPECT_DOUBLE_EQ(doc["reconstruction"]["accuracy"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(doc["reconstruction"]["completeness"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(doc["reconstruction"]["registered"]["accuracy"].get<double>(), 1.0);
    EXPECT_LT(doc["reconstruction"]["registered"]["registration"]["correction_translation_m"]
                  .get<double>(),
              1e-6);
    EXPECT_DOUBLE_EQ(doc["segmentation"]["kinds"]["all"]["mean_iou"].get<double>(), 1.0);
    EXPECT_EQ(doc["segmentation"]["frames"], 5);
    EXPECT_EQ(doc["timing"]["slam"]["tracking"]["count"], 5);
    EXPECT_DOUBLE_EQ(doc["timing"]["slam"]["tracking"]["median_ms"].get<double>(), 12.0);
    EXPECT_TRUE(std::filesystem::exists(run / "eval_ate.png"));
    EXPECT_TRUE(std::filesystem::exists(run / "eval_rpe.png"));
    EXPECT_TRUE(std::filesystem::exists(run / "eval_object_car_1.png"));
}

TEST(DfEvalRun, AnObjectWithoutGroundTruthIsAnError) {
    TempFolder seq, run;
    make_sequence_and_run(seq, run);
    std::filesystem::copy_file(run / "objects/car_1.txt", run / "objects/ghost.txt");
    std::string out;
    EXPECT_EQ(
        run_command(std::string(DF_EVAL_BIN) + " run --no-plots " + seq.str() + " " + run.str(),
                    &out),
        1);
    const json doc = test::read_json(run / "eval.json");
    ASSERT_EQ(doc["errors"].size(), 1u) << out;
    EXPECT_NE(doc["errors"][0].get<std::string>().find("objects/ghost.txt"), std::string::npos);
    EXPECT_TRUE(doc["objects"].contains("car_1"));  // the rest is still scored
}

TEST(DfEvalCli, ReconRegistersAMisplacedMapOntoItsModel) {
    TempFolder dir;
    // A floor and two walls, 2 cm apart; the map is the same surface 2 cm off along x and 1
    // degree turned.
    io::PointCloud model, map;
    for (int i = 0; i <= 50; ++i) {
        for (int j = 0; j <= 50; ++j) {
            model.positions.emplace_back(0.02 * i, 0.02 * j, 0.0);
            model.positions.emplace_back(0.02 * i, 0.0, 0.02 * j);
            model.positions.emplace_back(0.0, 0.02 * i, 0.02 * j);
        }
    }
    const Eigen::Isometry3d off = test::make_transform(M_PI / 180.0, Eigen::Vector3d(0, 0, 1),
                                                       Eigen::Vector3d(0.02, 0, 0));
    for (const auto& p : model.positions) map.positions.push_back(off * p);
    ASSERT_TRUE(io::write_ply(dir / "model.ply", model));
    ASSERT_TRUE(io::write_ply(dir / "map.ply", map));
    std::string out;
    ASSERT_EQ(run_command(std::string(DF_EVAL_BIN) + " recon " + (dir / "model.ply") +
                              " " + (dir / "map.ply") +
                              " --threshold 0.005 --register --json " +
                              (dir / "recon.json"),
                          &out),
              0)
        << out;
    const json doc = test::read_json(dir / "recon.json");
    EXPECT_LT(doc["reconstruction"]["accuracy"].get<double>(), 0.7) << out;
    EXPECT_GT(doc["registered"]["accuracy"].get<double>(), 0.999) << out;
    EXPECT_NEAR(doc["registered"]["registration"]["correction_rotation_deg"].get<double>(), 1.0,
                0.01);
    EXPECT_NE(out.find("After rigid registration"), std::string::npos) << out;
}

TEST(DfEvalCli, BadInputsNameTheFileAndLine) {
    TempFolder tmp;
    const Trajectory gt = test::smooth_trajectory(0.0, 30.0, 30);
    ASSERT_TRUE(io::write_tum_trajectory(tmp / "gt.txt", gt));
    write_file(tmp / "bad.txt", "# t tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0\n");
    ASSERT_TRUE(
        io::write_tum_trajectory(tmp / "late.txt", test::smooth_trajectory(500.0, 30.0, 30)));
    const std::string bin = DF_EVAL_BIN;
    std::string out;
    EXPECT_EQ(run_command(bin + " ate " + tmp / "gt.txt " + tmp / "missing.txt", &out), 1);
    EXPECT_NE(out.find(tmp / "missing.txt"), std::string::npos) << out;
    EXPECT_EQ(run_command(bin + " ate " + tmp / "gt.txt " + tmp / "bad.txt", &out), 1);
    EXPECT_NE(out.find(tmp / "bad.txt:3:"), std::string::npos) << out;
    EXPECT_EQ(run_command(bin + " rpe " + tmp / "gt.txt " + tmp / "late.txt", &out), 1);
    EXPECT_NE(out.find("[500.000000, 500.966667] s"), std::string::npos) << out;
    EXPECT_EQ(run_command(bin + " ate " + tmp / "gt.txt " + tmp / "late.txt", &out), 1);
    EXPECT_NE(out.find("no common stamps"), std::string::npos) << out;
    EXPECT_NE(out.find("[0.000000, 0.966667] s"), std::string::npos) << out;
}

}  // namespace
}  // namespace df::eval
