// Object maps: association by mask overlap, the two-sided alignment of object trajectories,
// and a run folder scored against a sequence where every answer is known.
#include "eval/object_maps.hpp"

#include <gtest/gtest.h>

#include "eval/object_association.hpp"
#include "eval/report.hpp"
#include "object_maps_scene.hpp"

namespace df::eval {
namespace {

using test::ObjectMapsScene;
using test::TempFolder;

/// A one-row label image from runs of (label, count).
cv::Mat row(std::initializer_list<std::pair<int, int>> runs) {
    std::vector<uint16_t> values;
    for (const auto& [label, count] : runs) values.insert(values.end(), count, label);
    return cv::Mat(values, true).reshape(1, 1);
}

std::vector<GtInstance> instances(std::initializer_list<std::pair<int, InstanceKind>> ids) {
    std::vector<GtInstance> out;
    for (const auto& [id, kind] : ids) {
        GtInstance inst;
        inst.id = id;
        inst.name = "inst" + std::to_string(id);
        inst.kind = kind;
        out.push_back(inst);
    }
    return out;
}

TEST(ObjectAssociation, GreedyByLargestIntersection) {
    // gt: instance 1 (10 px), 2 (10 px), 3 (10 px, non-rigid), 4 (5 px, rigid).
    const cv::Mat gt = row({{1, 10}, {2, 10}, {0, 10}, {3, 10}, {4, 5}});
    // est: 5 takes 6 px of instance 1 and 4 of instance 2; 6 the other 4 px of instance 1;
    // 8 has 4 of its 10 px on instance 2; 10 sits on the non-rigid instance 3.
    const cv::Mat est =
        row({{5, 6}, {6, 4}, {5, 4}, {8, 4}, {0, 2}, {8, 6}, {0, 4}, {10, 10}, {0, 5}});
    ASSERT_EQ(gt.cols, est.cols);
    MaskOverlap overlap;
    ASSERT_TRUE(overlap.add_frame(est, gt, "frame 0"));
    ASSERT_TRUE(overlap.add_frame(cv::Mat(), row({{1, 10}, {0, 45}}), "frame 1"));  // no masks
    ObjectAssociationConfig config;
    config.min_frames = 2;
    const auto gts = instances({{1, InstanceKind::kRigid},
                                {2, InstanceKind::kRigid},
                                {3, InstanceKind::kNonRigid},
                                {4, InstanceKind::kRigid}});
    const ObjectAssociation a = associate_objects(overlap, gts, {5, 6, 8, 10, 12}, config);
    EXPECT_EQ(a.frames, 2u);
    ASSERT_EQ(a.matches.size(), 1u);
    EXPECT_EQ(a.matches[0].est_id, 5);
    EXPECT_EQ(a.matches[0].gt_id, 1);
    EXPECT_EQ(a.matches[0].intersection_px, 6u);
    EXPECT_EQ(a.matches[0].frames, 1u);
    EXPECT_DOUBLE_EQ(a.matches[0].overlap, 0.6);
    EXPECT_DOUBLE_EQ(a.matches[0].iou, 6.0 / (10 + 20 - 6));  // over both frames
    ASSERT_EQ(a.duplicates.size(), 1u);
    EXPECT_EQ(a.duplicates[0].est_id, 6);
    EXPECT_EQ(a.duplicates[0].gt_id, 1);
    ASSERT_EQ(a.spurious.size(), 3u);  // by id: 8, 10, 12
    EXPECT_EQ(a.spurious[0].est_id, 8);
    EXPECT_EQ(a.spurious[0].best_gt_id, 2);
    EXPECT_NE(a.spurious[0].reason.find("40.0%"), std::string::npos) << a.spurious[0].reason;
    EXPECT_EQ(a.spurious[1].est_id, 10);
    EXPECT_NE(a.spurious[1].reason.find("non_rigid"), std::string::npos) << a.spurious[1].reason;
    EXPECT_EQ(a.spurious[2].est_id, 12);
    EXPECT_EQ(a.spurious[2].reason, "claimed no pixel");
    EXPECT_EQ(a.missed, std::vector<int>{});  // instance 2: one frame; 4 as well
    EXPECT_EQ(a.not_expected, (std::vector<int>{2, 4}));

    config.min_frames = 1;
    EXPECT_EQ(associate_objects(overlap, gts, {}, config).missed, (std::vector<int>{2, 4}));
    config.min_overlap = 0.3;  // now 8 qualifies for instance 2
    const ObjectAssociation loose = associate_objects(overlap, gts, {}, config);
    ASSERT_EQ(loose.matches.size(), 2u);
    EXPECT_EQ(loose.matches[1].est_id, 8);
    EXPECT_EQ(loose.matches[1].gt_id, 2);
}

TEST(ObjectAssociation, MismatchedImagesNameTheFrame) {
    MaskOverlap overlap;
    const Status s = overlap.add_frame(cv::Mat(2, 3, CV_16UC1, cv::Scalar(0)),
                                       cv::Mat(2, 4, CV_16UC1, cv::Scalar(0)), "run/x.png");
    EXPECT_FALSE(s);
    EXPECT_NE(s.message().find("run/x.png"), std::string::npos) << s.message();
}

TEST(ObjectTrajectory, BothFramesAlignedFromTheFirstPair) {
    const ObjectMapsScene scene;
    const Trajectory est = scene.estimated_car();  // W^-1 gt X^-1
    RpeConfig one_frame;
    one_frame.unit = DeltaUnit::kFrames;  // the car is tracked for a third of a second
    auto both =
        compute_object_errors(scene.car, est, ObjectAlignment{scene.W, true}, {}, one_frame);
    ASSERT_TRUE(both) << both.status().message();
    EXPECT_EQ(both->ate.alignment, AlignmentKind::kWorldAndObjectFirstPose);
    EXPECT_EQ(both->ate.pairs.size(), 10u);
    EXPECT_LT(both->ate.translation_m.max, 1e-9);
    EXPECT_LT(both->rotation_deg.max, 1e-6);
    EXPECT_TRUE(both->est_object_T_gt_object.isApprox(scene.X, 1e-9));
    ASSERT_TRUE(both->rpe);
    EXPECT_EQ(both->rpe->pairs.size(), 8u);  // TUM drops the pair ending on the last pose
    EXPECT_LT(both->rpe->translation_m.max, 1e-9);
    EXPECT_LT(both->rpe->rotation_deg.max, 1e-6);

    // Co-Fusion's alignment (one side) cannot absorb X: the car's turns show as errors.
    auto one_side = compute_object_errors(scene.car, est);
    ASSERT_TRUE(one_side);
    EXPECT_GT(one_side->rotation_deg.max, 0.5);

    // W given, X = identity; and X only (W = identity).
    Trajectory world_only, frame_only;
    for (const auto& p : scene.car) {
        world_only.push_back(test::transformed(scene.W.inverse(), p));
        io::StampedPose q = p;
        const Eigen::Isometry3d T = to_isometry(p) * scene.X.inverse();
        q.t = T.translation();
        q.q = Eigen::Quaterniond(T.linear());
        frame_only.push_back(q);
    }
    auto given = compute_object_errors(scene.car, world_only, ObjectAlignment{scene.W, false});
    ASSERT_TRUE(given);
    EXPECT_EQ(given->ate.alignment, AlignmentKind::kGivenWorld);
    EXPECT_LT(given->ate.translation_m.max, 1e-9);
    auto frame = compute_object_errors(scene.car, frame_only, ObjectAlignment{std::nullopt, true});
    ASSERT_TRUE(frame);
    EXPECT_LT(frame->ate.translation_m.max, 1e-9);
    EXPECT_LT(frame->rotation_deg.max, 1e-6);
    EXPECT_TRUE(frame->ate.gt_T_est.isApprox(Eigen::Isometry3d::Identity()));
}

Result<ObjectMapsResult> score_scene(const ObjectMapsScene& scene, const TempFolder& seq,
                                     const TempFolder& run) {
    scene.write_sequence(seq);
    scene.write_run(run);
    return score_object_maps(seq.str(), run.str(), scene.W);
}

TEST(ObjectMaps, ScoresARunWhoseAnswerIsKnown) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    auto r = score_scene(scene, seq, run);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE(r->errors.empty()) << r->errors.front();
    EXPECT_EQ(r->association.frames, 10u);  // frames 10 and 11 were not processed
    EXPECT_EQ(r->masks.frames_without_masks, 2u);
    ASSERT_EQ(r->objects.size(), 1u);
    const ObjectMapScore& car = r->objects[0];
    EXPECT_EQ(car.instance.name, "car_1");
    EXPECT_EQ(car.masks.est_id, 7);
    EXPECT_EQ(car.masks.frames, 7u);
    EXPECT_DOUBLE_EQ(car.masks.iou, 0.7);  // 7 of the car's 10 frames
    ASSERT_TRUE(car.trajectory);
    EXPECT_EQ(car.trajectory->ate.pairs.size(), 10u);
    EXPECT_LT(car.trajectory->ate.translation_m.max, 1e-6);  // stamps and poses via files
    EXPECT_LT(car.trajectory->rotation_deg.max, 1e-4);
    EXPECT_TRUE(car.trajectory->est_object_T_gt_object.isApprox(scene.X, 1e-6));
    ASSERT_TRUE(car.model) << car.model_note;
    EXPECT_DOUBLE_EQ(car.model->threshold_m, 0.01);
    EXPECT_DOUBLE_EQ(car.model->accuracy, 1.0);
    EXPECT_DOUBLE_EQ(car.model->completeness, 1.0);
    ASSERT_EQ(r->association.duplicates.size(), 1u);
    EXPECT_EQ(r->association.duplicates[0].est_id, 9);
    EXPECT_DOUBLE_EQ(r->association.duplicates[0].iou, 0.3);
    ASSERT_EQ(r->association.spurious.size(), 2u);
    EXPECT_EQ(r->association.spurious[0].est_id, 11);
    EXPECT_EQ(r->association.spurious[1].est_id, 13);
    EXPECT_EQ(r->association.missed, std::vector<int>{2});

    const nlohmann::json doc = to_json(*r);
    EXPECT_EQ(doc["objects"]["car_1"]["estimated_id"], 7);
    EXPECT_EQ(doc["objects"]["car_1"]["frames"], 7);
    EXPECT_EQ(doc["objects"]["car_1"]["trajectory"]["pairs"], 10);
    EXPECT_EQ(doc["objects"]["car_1"]["trajectory"]["world_alignment"], "camera ATE");
    EXPECT_DOUBLE_EQ(doc["objects"]["car_1"]["model"]["accuracy"].get<double>(), 1.0);
    EXPECT_EQ(doc["objects_duplicated"],
              nlohmann::json::parse(
                  R"([{"estimated_id": 9, "of": "car_1", "mask_iou": 0.3, "mask_overlap": 1.0,
                       "frames": 3}])"));
    EXPECT_EQ(doc["objects_spurious"], nlohmann::json::parse("[11, 13]"));
    EXPECT_EQ(doc["objects_missed"], nlohmann::json::parse(R"(["suitcase_1"])"));
    EXPECT_EQ(doc["objects_not_estimated"], doc["objects_missed"]);
    const std::string table = format_object_maps(*r, "Objects");
    EXPECT_NE(table.find("car_1"), std::string::npos) << table;
    EXPECT_NE(table.find("missed: suitcase_1"), std::string::npos) << table;
    EXPECT_NE(table.find("duplicated: 9 of car_1"), std::string::npos) << table;
}

TEST(ObjectMaps, APoseTwoCentimetresOffShowsInTheErrors) {
    TempFolder seq, run;
    ObjectMapsScene scene;
    scene.offset_frame = 4;
    auto r = score_scene(scene, seq, run);
    ASSERT_TRUE(r) << r.status().message();
    ASSERT_EQ(r->objects.size(), 1u);
    ASSERT_TRUE(r->objects[0].trajectory);
    const ObjectTrajectoryResult& t = *r->objects[0].trajectory;
    EXPECT_NEAR(t.ate.translation_m.max, 0.02, 1e-6);
    EXPECT_NEAR(t.ate.translation_m.rmse, 0.02 / std::sqrt(10.0), 1e-6);
    EXPECT_NEAR(t.ate.translation_m.mean, 0.002, 1e-6);
    EXPECT_NEAR(t.ate.pairs[4].error_m, 0.02, 1e-6);
    EXPECT_LT(t.rotation_deg.max, 1e-4);
}

TEST(ObjectMaps, AModelPlacedByAWrongFirstPoseIsRightAfterRegistration) {
    TempFolder seq, run;
    ObjectMapsScene scene;
    scene.offset_frame = 0;  // the first pose, which places the model, 2 cm off
    auto r = score_scene(scene, seq, run);
    ASSERT_TRUE(r) << r.status().message();
    const ObjectMapScore& car = r->objects.at(0);
    ASSERT_TRUE(car.model) << car.model_note;
    EXPECT_LT(car.model->accuracy, 0.7);
    ASSERT_TRUE(car.model_registered) << car.model_registration_note;
    EXPECT_GT(car.model_registered->accuracy, 0.99);
    EXPECT_GT(car.model_registered->completeness, 0.99);
    EXPECT_NEAR(car.model_registration->correction_translation_m, 0.02, 0.002);
    EXPECT_LT(car.model_registration->correction_rotation_deg, 0.2);
    const nlohmann::json doc = to_json(*r);
    EXPECT_GT(doc["objects"]["car_1"]["model_registered"]["accuracy"].get<double>(), 0.99);
    EXPECT_NEAR(doc["objects"]["car_1"]["model_registered"]["registration"]
                   ["correction_translation_m"]
                       .get<double>(),
                0.02, 0.002);
    const std::string table = format_object_maps(*r, "Objects");
    EXPECT_NE(table.find("car_1 model after rigid registration"), std::string::npos) << table;
}

TEST(ObjectMaps, AModelLeftInItsOwnFrameScoresLow) {
    TempFolder seq, run;
    ObjectMapsScene scene;
    scene.model_in_gt_frame = true;  // the scorer applies X^-1 to a model that did not need it
    auto r = score_scene(scene, seq, run);
    ASSERT_TRUE(r) << r.status().message();
    ASSERT_TRUE(r->objects.at(0).model);
    EXPECT_LT(r->objects[0].model->accuracy, 0.2);
}

TEST(ObjectMaps, WithoutWorldAlignmentSaysSo) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    scene.write_sequence(seq);
    scene.write_run(run);
    auto r = score_object_maps(seq.str(), run.str(), std::nullopt);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_FALSE(r->world_aligned);
    EXPECT_EQ(to_json(*r)["objects"]["car_1"]["trajectory"]["world_alignment"], "none");
    EXPECT_NE(format_object_maps(*r, "x").find("world alignment: none"), std::string::npos);
}

TEST(ObjectMaps, MalformedInputsNameTheFile) {
    TempFolder seq, run;
    const ObjectMapsScene scene;
    scene.write_sequence(seq);
    scene.write_run(run);
    test::write_file(run / "objects.json", R"({"objects": [{"id": 7}, {"id": "nine"}]})");
    auto r = score_object_maps(seq.str(), run.str(), scene.W);
    ASSERT_FALSE(r);
    EXPECT_NE(r.status().message().find(run / "objects.json: objects[1]"), std::string::npos)
        << r.status().message();

    scene.write_run(run);
    test::write_file(run / "objects/7.txt", "1.0 0 0 0 0 0 0 1\n1.1 0 0 zero 0 0 0 1\n");
    r = score_object_maps(seq.str(), run.str(), scene.W);
    ASSERT_TRUE(r) << r.status().message();  // the rest is still scored
    ASSERT_EQ(r->errors.size(), 1u);
    EXPECT_NE(r->errors[0].find(run / "objects/7.txt:2"), std::string::npos) << r->errors[0];
    EXPECT_EQ(r->association.missed, std::vector<int>{2});
}

}  // namespace
}  // namespace df::eval
