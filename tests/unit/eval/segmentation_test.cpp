// Instance segmentation scores on small hand-made label images with known IoUs.
#include "eval/segmentation.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "eval_test_support.hpp"

namespace df::eval {
namespace {

using test::TempFolder;
using test::write_file;

std::vector<GtInstance> instances() {
    return {{1, "car_1", 2, "car", InstanceKind::kRigid, "", ""},
            {2, "person_1", 0, "person", InstanceKind::kNonRigid, "", ""},
            {3, "thing_1", -1, "", InstanceKind::kUnknown, "", ""}};
}

/// 10x10: instance 1 = rows 0-4 x cols 0-4 (25 px), 2 = rows 5-9 x cols 5-9 (25 px),
/// 3 = rows 0-1 x cols 7-9 (6 px).
cv::Mat gt_frame() {
    cv::Mat gt(10, 10, CV_16UC1, cv::Scalar(0));
    gt(cv::Rect(0, 0, 5, 5)).setTo(1);
    gt(cv::Rect(5, 5, 5, 5)).setTo(2);
    gt(cv::Rect(7, 0, 3, 2)).setTo(3);
    return gt;
}

/// Label 7 = rows 0-4 x cols 0-3 (IoU 20/25 with 1); label 9 = rows 5-9 x cols 3-9 (IoU 25/35
/// with 2); label 4 = rows 0-1 x col 9 (IoU 2/6 with 3: below 0.5, a false positive).
cv::Mat pred_frame() {
    cv::Mat pred(10, 10, CV_16UC1, cv::Scalar(0));
    pred(cv::Rect(0, 0, 4, 5)).setTo(7);
    pred(cv::Rect(3, 5, 7, 5)).setTo(9);
    pred(cv::Rect(9, 0, 1, 2)).setTo(4);
    return pred;
}

TEST(Segmentation, OneFrameMatchesByIou) {
    auto m = match_frame(gt_frame(), pred_frame(), 0.5);
    ASSERT_TRUE(m) << m.status().to_string();
    ASSERT_EQ(m->instances.size(), 3u);
    EXPECT_EQ(m->instances[0].pred_label, 7);
    EXPECT_DOUBLE_EQ(m->instances[0].iou, 20.0 / 25);
    EXPECT_EQ(m->instances[1].pred_label, 9);
    EXPECT_DOUBLE_EQ(m->instances[1].iou, 25.0 / 35);
    EXPECT_EQ(m->instances[2].pred_label, 0);
    EXPECT_EQ(m->predicted_segments, 3u);
    EXPECT_EQ(m->unmatched_segments, 1u);
    // With a lower threshold, label 4 matches instance 3.
    auto loose = match_frame(gt_frame(), pred_frame(), 0.3);
    ASSERT_TRUE(loose);
    EXPECT_EQ(loose->instances[2].pred_label, 4);
    EXPECT_DOUBLE_EQ(loose->instances[2].iou, 2.0 / 6);
}

TEST(Segmentation, ScoresOverFramesPerInstanceAndKind) {
    SegmentationScorer scorer(instances(), {});
    ASSERT_TRUE(scorer.add_frame(gt_frame(), pred_frame(), "frame 1"));
    ASSERT_TRUE(scorer.add_frame(gt_frame(), cv::Mat(), "frame 2"));  // nothing predicted
    const SegmentationResult r = scorer.result();
    EXPECT_EQ(r.frames, 2u);
    ASSERT_EQ(r.instances.size(), 3u);
    const InstanceScore& car = r.instances[0];
    EXPECT_EQ(car.frames_visible, 2u);
    EXPECT_EQ(car.frames_matched, 1u);
    EXPECT_DOUBLE_EQ(car.mean_iou, 0.8 / 2);
    EXPECT_DOUBLE_EQ(car.mean_precision, 1.0);
    EXPECT_DOUBLE_EQ(car.mean_recall, 0.8 / 2);
    EXPECT_DOUBLE_EQ(car.detection_recall, 0.5);
    const InstanceScore& person = r.instances[1];
    EXPECT_DOUBLE_EQ(person.mean_iou, 25.0 / 35 / 2);
    EXPECT_DOUBLE_EQ(person.mean_precision, 25.0 / 35);
    EXPECT_DOUBLE_EQ(person.mean_recall, 0.5);
    EXPECT_DOUBLE_EQ(r.instances[2].mean_iou, 0.0);

    EXPECT_EQ(r.predicted_segments, 3u);
    EXPECT_EQ(r.false_positive_segments, 1u);
    EXPECT_DOUBLE_EQ(r.detection_precision, 2.0 / 3);
    EXPECT_DOUBLE_EQ(r.detection_recall, 2.0 / 6);
    ASSERT_EQ(r.kinds.size(), 4u);
    EXPECT_EQ(r.kinds[0].kind, "rigid");
    EXPECT_DOUBLE_EQ(r.kinds[0].mean_iou, 0.4);
    EXPECT_EQ(r.kinds[1].kind, "non_rigid");
    EXPECT_DOUBLE_EQ(r.kinds[1].detection_recall, 0.5);
    EXPECT_EQ(r.kinds[2].kind, "unknown");
    EXPECT_DOUBLE_EQ(r.kinds[2].detection_recall, 0.0);
    EXPECT_EQ(r.kinds[3].kind, "all");
    EXPECT_EQ(r.kinds[3].visible, 6u);
    EXPECT_DOUBLE_EQ(r.kinds[3].mean_iou, (0.8 + 25.0 / 35) / 6);
}

TEST(Segmentation, UnlistedGroundTruthIdAndWrongSizeAreErrors) {
    SegmentationScorer scorer({{1, "car_1", 2, "car", InstanceKind::kRigid, "", ""}}, {});
    const Status unlisted = scorer.add_frame(gt_frame(), pred_frame(), "instances/1.0.png");
    ASSERT_FALSE(unlisted);
    EXPECT_NE(unlisted.message().find("instances/1.0.png"), std::string::npos);
    EXPECT_NE(unlisted.message().find("id 2"), std::string::npos) << unlisted.message();
    auto wrong = match_frame(gt_frame(), cv::Mat(5, 5, CV_16UC1, cv::Scalar(0)), 0.5);
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.status().message().find("5x5"), std::string::npos);
}

TEST(Segmentation, FoldersPairByStampAndCountMissingFrames) {
    TempFolder seq, pred;
    write_file(seq / "instances.json",
               R"({"instances": [
                 {"id": 1, "name": "car_1", "class_id": 2, "class_name": "car", "kind": "rigid",
                  "model": "models/car_1.ply", "trajectory": "objects/car_1.txt"},
                 {"id": 2, "name": "person_1", "class_id": 0, "class_name": "person",
                  "kind": "non_rigid", "model": null, "trajectory": "objects/person_1.txt"},
                 {"id": 3, "name": "thing_1", "class_id": -1, "class_name": "unknown",
                  "kind": "unknown", "model": null, "trajectory": "objects/thing_1.txt"}]})");
    std::filesystem::create_directories(seq / "instances");
    ASSERT_TRUE(cv::imwrite(seq / "instances/1.000000.png", gt_frame()));
    ASSERT_TRUE(cv::imwrite(seq / "instances/1.033333.png", gt_frame()));
    ASSERT_TRUE(cv::imwrite(pred / "1.000000.png", pred_frame()));  // the second one is missing
    auto r = score_segmentation_folders(seq.str(), pred.str());
    ASSERT_TRUE(r) << r.status().to_string();
    EXPECT_EQ(r->frames, 2u);
    EXPECT_EQ(r->frames_without_prediction, 1u);
    EXPECT_DOUBLE_EQ(r->instances[0].mean_iou, 0.4);

    SegmentationConfig skip;
    skip.skip_missing = true;
    auto skipped = score_segmentation_folders(seq.str(), pred.str(), skip);
    ASSERT_TRUE(skipped) << skipped.status().to_string();
    EXPECT_EQ(skipped->frames, 1u);
    EXPECT_DOUBLE_EQ(skipped->instances[0].mean_iou, 0.8);

    write_file(seq / "instances.json", R"({"instances": [{"id": 1, "kind": "solid"}]})");
    auto bad = score_segmentation_folders(seq.str(), pred.str());
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.status().message().find("instances[0]: kind 'solid'"), std::string::npos)
        << bad.status().message();
}

TEST(Segmentation, MovingOnlyScoresAnInstanceWhereItsTrajectoryMoved) {
    TempFolder seq, pred;
    write_file(seq / "instances.json",
               R"({"instances": [
                 {"id": 1, "name": "car_1", "class_id": 2, "class_name": "car", "kind": "rigid",
                  "model": null, "trajectory": "objects/car_1.txt"},
                 {"id": 2, "name": "person_1", "class_id": 0, "class_name": "person",
                  "kind": "non_rigid", "model": null, "trajectory": null},
                 {"id": 3, "name": "thing_1", "class_id": -1, "class_name": "unknown",
                  "kind": "unknown", "model": null, "trajectory": null}]})");
    // The car stands from the first frame to the second and moves 2 cm to the third.
    write_file(seq / "objects/car_1.txt",
               "1.000000 0 0 0 0 0 0 1\n1.033333 0 0 0 0 0 0 1\n1.066667 0.02 0 0 0 0 0 1\n");
    std::filesystem::create_directories(seq / "instances");
    for (const char* stamp : {"1.000000", "1.033333", "1.066667"}) {
        ASSERT_TRUE(cv::imwrite(seq / ("instances/" + std::string(stamp) + ".png"), gt_frame()));
        ASSERT_TRUE(cv::imwrite(pred / (std::string(stamp) + ".png"), pred_frame()));
    }
    SegmentationConfig moving;
    moving.moving_min_m = 0.01;
    auto r = score_segmentation_folders(seq.str(), pred.str(), moving);
    ASSERT_TRUE(r) << r.status().to_string();
    EXPECT_EQ(r->frames, 3u);
    ASSERT_EQ(r->instances.size(), 1u) << "only the car, and only where it moved";
    EXPECT_EQ(r->instances[0].instance.name, "car_1");
    EXPECT_EQ(r->instances[0].frames_visible, 1u);
    EXPECT_DOUBLE_EQ(r->instances[0].mean_iou, 0.8);
    auto all = score_segmentation_folders(seq.str(), pred.str());
    ASSERT_TRUE(all) << all.status().to_string();
    EXPECT_EQ(all->instances[0].frames_visible, 3u);
}

}  // namespace
}  // namespace df::eval
