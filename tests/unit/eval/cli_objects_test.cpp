// The df_eval executable on object maps: `run` with RUN_DIR/objects.json, and `object` with
// --world and --body-align.
#include <gtest/gtest.h>

#include <cstdio>

#include "eval_test_support.hpp"
#include "object_maps_scene.hpp"

namespace df::eval {
namespace {

using nlohmann::json;
using test::ObjectMapsScene;
using test::run_command;
using test::TempFolder;

std::string run_eval(const std::string& args, std::string* out) {
    const int status = run_command(std::string(DF_EVAL_BIN) + " " + args, out);
    return std::to_string(status);
}

TEST(DfEvalRunObjects, AssociatesObjectMapsByMasks) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    scene.write_sequence(seq);
    scene.write_run(run);
    std::string out;
    ASSERT_EQ(run_eval("run " + seq.str() + " " + run.str(), &out), "0") << out;
    const json doc = test::read_json(run / "eval.json");
    ASSERT_TRUE(doc.is_object()) << out;
    EXPECT_TRUE(doc["errors"].empty()) << doc["errors"];
    const json& car = doc["objects"]["car_1"];
    EXPECT_EQ(car["estimated_id"], 7);
    EXPECT_DOUBLE_EQ(car["mask_iou"].get<double>(), 0.7);
    EXPECT_EQ(car["frames"], 7);
    // W comes from the camera ATE here, X from the first pose pair.
    EXPECT_EQ(car["trajectory"]["world_alignment"], "camera ATE");
    EXPECT_EQ(car["trajectory"]["pairs"], 10);
    EXPECT_LT(car["trajectory"]["translation_m"]["rmse"].get<double>(), 1e-6);
    EXPECT_LT(car["trajectory"]["rotation_deg"]["max"].get<double>(), 1e-4);
    EXPECT_DOUBLE_EQ(car["model"]["accuracy"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(car["model"]["completeness"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(car["model"]["threshold_m"].get<double>(), 0.01);
    EXPECT_EQ(doc["objects_duplicated"][0]["estimated_id"], 9);
    EXPECT_EQ(doc["objects_duplicated"][0]["of"], "car_1");
    EXPECT_EQ(doc["objects_spurious"], json::parse("[11, 13]"));
    EXPECT_EQ(doc["objects_missed"], json::parse(R"(["suitcase_1"])"));
    EXPECT_EQ(doc["objects_not_estimated"], json::parse(R"(["suitcase_1"])"));
    EXPECT_NE(out.find("missed: suitcase_1"), std::string::npos) << out;
    EXPECT_TRUE(std::filesystem::exists(run / "eval_object_car_1.png"));

    ASSERT_EQ(
        run_eval("run --no-plots --object-threshold 0.002 " + seq.str() + " " + run.str(), &out),
        "0")
        << out;
    EXPECT_DOUBLE_EQ(test::read_json(run / "eval.json")["objects"]["car_1"]["model"]["threshold_m"]
                         .get<double>(),
                     0.002);
}

TEST(DfEvalRunObjects, MalformedObjectsJsonIsNamedAndTheRestScored) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    scene.write_sequence(seq);
    scene.write_run(run);
    test::write_file(run / "objects.json", R"({"objects": [{"id": 7,}]})");
    std::string out;
    EXPECT_EQ(run_eval("run --no-plots " + seq.str() + " " + run.str(), &out), "1") << out;
    const json doc = test::read_json(run / "eval.json");
    ASSERT_EQ(doc["errors"].size(), 1u) << out;
    EXPECT_NE(doc["errors"][0].get<std::string>().find(run / "objects.json"), std::string::npos)
        << doc["errors"];
    EXPECT_LT(doc["camera"]["ate"]["translation_m"]["rmse"].get<double>(), 1e-6);
}

TEST(DfEvalRunObjects, WithoutCameraTrajectoryTheWorldsAreNotAligned) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    scene.write_sequence(seq);
    scene.write_run(run);
    std::filesystem::remove(run / "trajectory.txt");
    std::string out;
    EXPECT_EQ(run_eval("run --no-plots " + seq.str() + " " + run.str(), &out), "0") << out;
    const json doc = test::read_json(run / "eval.json");
    EXPECT_EQ(doc["objects"]["car_1"]["trajectory"]["world_alignment"], "none");
    EXPECT_NE(out.find("world alignment: none"), std::string::npos) << out;
}

TEST(DfEvalObject, WorldAndBodyAlignment) {
    TempFolder tmp;
    const ObjectMapsScene scene;
    ASSERT_TRUE(io::write_tum_trajectory(tmp / "gt.txt", scene.car));
    ASSERT_TRUE(io::write_tum_trajectory(tmp / "est.txt", scene.estimated_car()));
    const Eigen::Quaterniond q(scene.W.linear());
    const Eigen::Vector3d& t = scene.W.translation();
    char world[256];
    std::snprintf(world, sizeof world, "'%.17g %.17g %.17g %.17g %.17g %.17g %.17g'", t.x(), t.y(),
                  t.z(), q.x(), q.y(), q.z(), q.w());
    const std::string files = tmp / "gt.txt " + tmp / "est.txt";
    std::string out;
    ASSERT_EQ(run_eval("object " + files + " --world " + world + " --body-align --json " +
                           tmp / "both.json",
                       &out),
              "0")
        << out;
    const json both = test::read_json(tmp / "both.json")["object"];
    EXPECT_LT(both["ate"]["translation_m"]["max"].get<double>(), 1e-6) << out;
    EXPECT_LT(both["rotation_deg"]["max"].get<double>(), 1e-4);
    EXPECT_EQ(both["ate"]["alignment_gt_T_est"]["kind"], "world_and_object_first_pose");
    EXPECT_TRUE(both.contains("alignment_est_object_T_gt_object"));

    // Without --body-align the object frame offset stays in the errors.
    ASSERT_EQ(
        run_eval("object " + files + " --world " + world + " --json " + tmp / "world.json", &out),
        "0")
        << out;
    EXPECT_GT(test::read_json(tmp / "world.json")["object"]["rotation_deg"]["max"].get<double>(),
              10.0);
    EXPECT_EQ(run_eval("object " + files + " --world '1 2 3'", &out), "1");
    EXPECT_NE(out.find("--world: expected 7 numbers"), std::string::npos) << out;
}

}  // namespace
}  // namespace df::eval
