#pragma once
/// A sequence and a run with object maps whose scores are known, for the object map tests.
///
/// Ground truth (12 frames, 64x48 instance images): car_1 (rigid, id 1) in frames 0..9, moving
/// one pixel a frame; suitcase_1 (rigid, id 2) and person_1 (non-rigid, id 3) in every frame.
/// The run numbers its objects itself: 7 claims the car's pixels in frames 0..6, 9 in frames
/// 7..9 (a duplicate), 11 a patch of background (spurious), 13 the person (spurious: not rigid);
/// the suitcase has no object (missed). Frames 10 and 11 have no object_masks file (the run did
/// not process them: not scored).
/// The run's world is W^-1 of the ground truth's and its car frame X^-1 of the car's: object 7's
/// poses are W^-1 gt_i X^-1 and its model X p for every ground-truth model point p.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "eval_test_support.hpp"
#include "io/ply/ply.hpp"
#include "io/tum/stamp.hpp"
#include "io/tum/trajectory.hpp"

namespace df::eval::test {

struct ObjectMapsScene {
    /// gt_T_est of the worlds: 40 deg.
    Eigen::Isometry3d W = make_transform(0.7, {0.3, 1, 0.2}, {0.5, -1, 2});
    /// est_object_T_gt_object: -52 deg.
    Eigen::Isometry3d X = make_transform(-0.9, {1, 0.2, -0.4}, {0.1, 0.3, -0.2});
    Trajectory camera = smooth_trajectory(1.0, 30.0, 60);  ///< ground-truth world_T_camera
    Trajectory car;                                        ///< ground-truth world_T_object
    std::vector<Eigen::Vector3d> car_model;                ///< car_1 frame
    /// Moves object 7's pose of this frame by 2 cm (-1: none).
    int offset_frame = -1;
    /// Writes object 7's model in the ground-truth car frame (forgetting X).
    bool model_in_gt_frame = false;

    static constexpr int kFrames = 12;
    static constexpr int kCarFrames = 10;
    static cv::Rect car_rect(int frame) { return {4 + frame, 10, 16, 12}; }  // 192 px

    ObjectMapsScene() {
        const Eigen::Isometry3d street = make_transform(0.3, {0, 0, 1}, {2, 0.5, 0});
        for (int i = 0; i < kFrames; ++i) car.push_back(transformed(street, camera[i]));
        for (int a = 0; a <= 30; ++a) {  // the four sides of a 30 x 20 x 15 cm box, 1 cm apart
            for (int h = 0; h <= 15; ++h) {
                car_model.emplace_back(0.01 * a - 0.15, -0.1, 0.01 * h);
                car_model.emplace_back(0.01 * a - 0.15, 0.1, 0.01 * h);
                if (a <= 20) car_model.emplace_back(-0.15, 0.01 * a - 0.1, 0.01 * h);
                if (a <= 20) car_model.emplace_back(0.15, 0.01 * a - 0.1, 0.01 * h);
            }
        }
    }

    static std::string png_name(const io::StampedPose& p) {
        return io::stamp_text(std::llround(p.stamp_s * 1e9)) + ".png";
    }

    /// object 7's estimated poses: W^-1 gt_i X^-1 for the frames it tracked.
    Trajectory estimated_car() const {
        Trajectory est;
        for (int i = 0; i < kCarFrames; ++i) {
            io::StampedPose p = car[static_cast<size_t>(i)];
            const Eigen::Isometry3d T = W.inverse() * to_isometry(p) * X.inverse();
            p.t = T.translation();
            p.q = Eigen::Quaterniond(T.linear());
            if (i == offset_frame) p.t += Eigen::Vector3d(0.0, 0.02, 0.0);
            est.push_back(p);
        }
        return est;
    }

    void write_sequence(const TempFolder& seq) const {
        std::filesystem::create_directories(seq / "instances");
        std::filesystem::create_directories(seq / "objects");
        std::filesystem::create_directories(seq / "models");
        write_file(seq / "instances.json", R"({"instances": [
            {"id": 1, "name": "car_1", "class_id": 2, "class_name": "car", "kind": "rigid",
             "model": "models/car_1.ply", "trajectory": "objects/car_1.txt"},
            {"id": 2, "name": "suitcase_1", "class_id": 28, "class_name": "suitcase",
             "kind": "rigid", "model": "models/suitcase_1.ply",
             "trajectory": "objects/suitcase_1.txt"},
            {"id": 3, "name": "person_1", "class_id": 0, "class_name": "person",
             "kind": "non_rigid", "model": null, "trajectory": "objects/person_1.txt"}]})");
        ASSERT_TRUE(io::write_tum_trajectory(seq / "groundtruth.txt", camera));
        ASSERT_TRUE(io::write_tum_trajectory(seq / "objects/car_1.txt", car));
        io::PointCloud model;
        model.positions = car_model;
        io::PlyWriteOptions ascii;
        ascii.format = io::PlyFormat::kAscii;
        ASSERT_TRUE(io::write_ply(seq / "models/car_1.ply", model, ascii));
        for (int i = 0; i < kFrames; ++i) {
            cv::Mat gt(48, 64, CV_16UC1, cv::Scalar(0));
            if (i < kCarFrames) gt(car_rect(i)).setTo(1);
            gt(cv::Rect(44, 4, 10, 8)).setTo(2);
            gt(cv::Rect(30, 24, 8, 20)).setTo(3);
            ASSERT_TRUE(cv::imwrite(seq / ("instances/" + png_name(camera[i])), gt));
        }
    }

    void write_run(const TempFolder& run) const {
        std::filesystem::create_directories(run / "objects");
        std::filesystem::create_directories(run / "object_masks");
        write_file(run / "objects.json", R"({"objects": [
            {"id": 7, "class_id": 2, "class_name": "car", "first_frame": 0, "last_frame": 9,
             "frames_tracked": 10, "surfels": 4000, "state": "active",
             "trajectory": "objects/7.txt", "model": "objects/7.ply"},
            {"id": 9, "class_id": 2, "class_name": "car", "state": "retired",
             "trajectory": "objects/9.txt", "model": "objects/9.ply"},
            {"id": 11, "class_id": 28, "class_name": "suitcase", "trajectory": "objects/11.txt",
             "model": null},
            {"id": 13, "class_id": 0, "class_name": "person", "trajectory": "objects/13.txt"}]})");
        Trajectory est_camera;
        for (const auto& p : camera) est_camera.push_back(transformed(W.inverse(), p));
        ASSERT_TRUE(io::write_tum_trajectory(run / "trajectory.txt", est_camera));
        const Trajectory est = estimated_car();
        ASSERT_TRUE(io::write_tum_trajectory(run / "objects/7.txt", est));
        ASSERT_TRUE(io::write_tum_trajectory(run / "objects/9.txt", est));
        ASSERT_TRUE(io::write_tum_trajectory(run / "objects/11.txt", est));
        io::PointCloud model;
        for (const auto& p : car_model) model.positions.push_back(model_in_gt_frame ? p : X * p);
        ASSERT_TRUE(io::write_ply(run / "objects/7.ply", model));  // binary float
        for (int i = 0; i < kCarFrames; ++i) {
            cv::Mat masks(48, 64, CV_16UC1, cv::Scalar(0));
            masks(car_rect(i)).setTo(i < 7 ? 7 : 9);
            masks(cv::Rect(0, 40, 6, 6)).setTo(11);
            masks(cv::Rect(30, 24, 8, 20)).setTo(13);
            ASSERT_TRUE(cv::imwrite(run / ("object_masks/" + png_name(camera[i])), masks));
        }
        // Per-frame segment images of the run live in segments/; a stray PNG in objects/ is
        // ignored.
        ASSERT_TRUE(cv::imwrite(run / ("objects/" + png_name(camera[0])),
                                cv::Mat(48, 64, CV_16UC1, cv::Scalar(5))));
    }
};

}  // namespace df::eval::test
