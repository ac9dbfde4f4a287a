// df_detect without the downloaded model: NMS, config helpers, bad model files, and the Darknet
// and ONNX paths end to end on tiny models written by the test (tiny_models.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "detect/detector.hpp"
#include "tiny_models.hpp"

namespace df::detect {
namespace {

namespace fs = std::filesystem;

class TempDir {
  public:
    TempDir() : path_(fs::temp_directory_path() / ("df_detect_test_" + std::to_string(getpid()))) {
        fs::create_directories(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    std::string operator/(const std::string& name) const { return (path_ / name).string(); }

  private:
    fs::path path_;
};

Detection det(float x, float y, float w, float h, int class_id, float score) {
    Detection d;
    d.box = {x, y, w, h};
    d.class_id = class_id;
    d.score = score;
    return d;
}

void expect_box_near(const cv::Rect2f& a, const cv::Rect2f& b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.width, b.width, tol);
    EXPECT_NEAR(a.height, b.height, tol);
}

TEST(DetectNmsTest, SuppressesOverlapsOfTheSameClassOnly) {
    // B overlaps A with IoU 81/119 = 0.68; C is B's box but another class; D is apart.
    std::vector<Detection> in = {det(1, 1, 10, 10, 0, 0.8f), det(20, 20, 10, 10, 0, 0.6f),
                                 det(0, 0, 10, 10, 0, 0.9f), det(1, 1, 10, 10, 1, 0.7f)};
    EXPECT_NEAR(iou(in[0].box, in[2].box), 81.f / 119.f, 1e-5f);
    auto out = nms_per_class(in, 0.45f);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_FLOAT_EQ(out[0].score, 0.9f);
    EXPECT_FLOAT_EQ(out[1].score, 0.7f);
    EXPECT_FLOAT_EQ(out[2].score, 0.6f);
    EXPECT_EQ(nms_per_class(in, 0.7f).size(), 4u);  // 0.68 < 0.7 keeps B
}

TEST(DetectNmsTest, IouOfDisjointAndEmptyBoxesIsZero) {
    EXPECT_FLOAT_EQ(iou({0, 0, 1, 1}, {2, 2, 1, 1}), 0.f);
    EXPECT_FLOAT_EQ(iou({0, 0, 0, 0}, {0, 0, 0, 0}), 0.f);
    EXPECT_FLOAT_EQ(iou({0, 0, 2, 2}, {0, 0, 2, 2}), 1.f);
}

TEST(DetectConfigTest, ClassKindsAndThresholds) {
    DetectorConfig c;
    EXPECT_EQ(c.kind_of("person"), ClassKind::kNonRigid);
    EXPECT_EQ(c.kind_of("car"), ClassKind::kRigid);
    EXPECT_EQ(c.kind_of("cup"), ClassKind::kRigid);
    EXPECT_EQ(c.kind_of("horse"), ClassKind::kIgnored);
    c.class_score_thresholds["car"] = 0.6f;
    EXPECT_FLOAT_EQ(c.threshold_for("car"), 0.6f);
    EXPECT_FLOAT_EQ(c.threshold_for("dog"), 0.25f);
    ASSERT_EQ(coco_names().size(), 80u);
    EXPECT_EQ(coco_names()[0], "person");
    EXPECT_EQ(coco_names()[79], "toothbrush");
}

TEST(DetectBadModelTest, MissingFolderNamesItAndSetup) {
    DetectorConfig c;
    c.model_path = "/nonexistent/yolov5s";
    auto d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kNotFound);
    EXPECT_NE(d.status().message().find("/nonexistent/yolov5s"), std::string::npos);
    EXPECT_NE(d.status().message().find("deploy/setup.sh"), std::string::npos);
}

TEST(DetectBadModelTest, GarbageModelJsonAndTruncatedShard) {
    TempDir dir;
    DetectorConfig c;
    c.model_path = dir / "";
    std::ofstream(dir / "model.json") << "<html>not json";
    auto d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(d.status().message().find(dir / "model.json"), std::string::npos)
        << d.status().message();
    EXPECT_NE(d.status().message().find("not valid JSON"), std::string::npos);

    // A valid manifest of 2 shards (4 MiB, TFJS's shard size, + 40 bytes) whose first shard is
    // cut short.
    std::ofstream(dir / "model.json")
        << R"({"modelTopology": {"node": []}, "weightsManifest": [{"paths": ["s1.bin", "s2.bin"],
              "weights": [{"name": "a", "shape": [1048576], "dtype": "float32"},
                          {"name": "b", "shape": [10], "dtype": "float32"}]}]})";
    std::ofstream(dir / "s1.bin") << std::string(1000, '\0');
    std::ofstream(dir / "s2.bin") << std::string(40, '\0');
    d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(d.status().message().find(dir / "s1.bin"), std::string::npos) << d.status().message();

    fs::remove(dir / "s2.bin");
    d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kNotFound);
    EXPECT_NE(d.status().message().find(dir / "s2.bin"), std::string::npos) << d.status().message();
}

TEST(DetectBadModelTest, InputSizeMustBeMultipleOf32) {
    DetectorConfig c;
    c.input_width = 500;
    auto d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(d.status().message().find("500x640"), std::string::npos) << d.status().message();
}

TEST(DetectBadModelTest, NegativeOrHugeWeightShapeIsNamedNotWrapped) {
    // A shape with -1 used to wrap the byte count ("needs 18446743919119700504 bytes").
    TempDir dir;
    DetectorConfig c;
    c.model_path = dir / "";
    for (const char* shape : {"[3, -1, 16]", "[100000, 100000, 100000]"}) {
        std::ofstream(dir / "model.json")
            << R"({"modelTopology": {"node": []}, "weightsManifest": [{"paths": ["s1.bin"],
                  "weights": [{"name": "conv/w", "shape": )"
            << shape << R"(, "dtype": "float32"}]}]})";
        std::ofstream(dir / "s1.bin") << std::string(40, '\0');
        auto d = open_detector(c);
        ASSERT_FALSE(d.is_ok()) << shape;
        EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
        EXPECT_NE(d.status().message().find("weight conv/w has shape ["), std::string::npos)
            << d.status().message();
        EXPECT_NE(d.status().message().find("each dimension must be >= 0"), std::string::npos)
            << d.status().message();
        EXPECT_EQ(d.status().message().find("needs"), std::string::npos) << d.status().message();
    }
}

TEST(DetectBadModelTest, InputSizeAndThresholdsOutOfRangeAreRefusedBeforeOpenCv) {
    DetectorConfig c;
    c.input_width = 100000 / 32 * 32;  // a multiple of 32, but far beyond what a network takes
    auto d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_NE(d.status().message().find("input_width is 100000, allowed: >= 32 and <= 2048 [px]"),
              std::string::npos)
        << d.status().message();
    c = DetectorConfig{};
    c.nms_iou_threshold = 2.f;
    d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_NE(d.status().message().find("nms_iou_threshold is 2, allowed: >= 0 and <= 1"),
              std::string::npos)
        << d.status().message();
    c = DetectorConfig{};
    c.score_threshold = std::nanf("");
    d = open_detector(c);
    ASSERT_FALSE(d.is_ok());
    EXPECT_NE(d.status().message().find("score_threshold is nan"), std::string::npos)
        << d.status().message();
}

DetectorConfig tiny_config(ModelKind kind, const std::string& model,
                           const std::string& weights = "") {
    DetectorConfig c;
    c.kind = kind;
    c.model_path = model;
    c.weights_path = weights;
    c.input_width = c.input_height = 32;
    return c;
}

TEST(DetectDarknetTest, TinyYoloGivesItsBoxInImagePixels) {
    TempDir dir;
    test::write_tiny_darknet(dir / "tiny.cfg", dir / "tiny.weights");
    auto d =
        open_detector(tiny_config(ModelKind::kDarknet, dir / "tiny.cfg", dir / "tiny.weights"));
    ASSERT_TRUE(d.is_ok()) << d.status().to_string();
    // 64x32 image -> scale 0.5, 8 rows of padding above: net box centre (16, 16), 10x13 ->
    // image centre (32, 16), 20x26.
    auto out = (*d)->detect(cv::Mat(32, 64, CV_8UC3, cv::Scalar(0, 0, 0)));
    ASSERT_TRUE(out.is_ok()) << out.status().to_string();
    ASSERT_EQ(out->size(), 1u);
    EXPECT_EQ((*out)[0].class_name, "car");
    EXPECT_EQ((*out)[0].class_id, 2);
    const float expected_score = 1.f / (1.f + std::exp(-6.f)) / (1.f + std::exp(-3.f));
    EXPECT_NEAR((*out)[0].score, expected_score, 1e-4f);  // objectness x class = 0.950
    expect_box_near((*out)[0].box, {22, 3, 20, 26}, 0.5f);

    auto c = tiny_config(ModelKind::kDarknet, dir / "tiny.cfg", dir / "tiny.weights");
    c.class_score_thresholds["car"] = 0.96f;  // above 0.950
    auto strict = open_detector(c);
    ASSERT_TRUE(strict.is_ok());
    EXPECT_TRUE((*strict)->detect(cv::Mat(32, 32, CV_8UC3))->empty());
    c.class_score_thresholds.clear();
    auto& rigid = c.classes.rigid;
    rigid.erase(std::remove(rigid.begin(), rigid.end(), "car"), rigid.end());
    c.drop_ignored_classes = true;
    auto rigid_only = open_detector(c);
    ASSERT_TRUE(rigid_only.is_ok());
    EXPECT_TRUE((*rigid_only)->detect(cv::Mat(32, 32, CV_8UC3))->empty());
    EXPECT_EQ((*rigid_only)->detect(cv::Mat()).status().code(), StatusCode::kInvalidArgument);
}

TEST(DetectDarknetTest, WrongWeightsAndMissingFilesAreErrors) {
    TempDir dir;
    test::write_tiny_darknet(dir / "tiny.cfg", dir / "short.weights", 100);
    auto d =
        open_detector(tiny_config(ModelKind::kDarknet, dir / "tiny.cfg", dir / "short.weights"));
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(d.status().message().find(dir / "short.weights"), std::string::npos)
        << d.status().message();

    d = open_detector(tiny_config(ModelKind::kDarknet, dir / "tiny.cfg", dir / "none.weights"));
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kNotFound);
    EXPECT_NE(d.status().message().find(dir / "none.weights"), std::string::npos);

    std::ofstream(dir / "bad.cfg") << "[net]\nwidth=32\n[nonsense_layer]\nfoo=1\n";
    d = open_detector(tiny_config(ModelKind::kDarknet, dir / "bad.cfg", dir / "short.weights"));
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
}

TEST(DetectOnnxTest, TinyYolov8LayoutGivesItsBoxInImagePixels) {
    TempDir dir;
    test::write_tiny_onnx(dir / "tiny.onnx");
    auto d = open_detector(tiny_config(ModelKind::kOnnx, dir / "tiny.onnx"));
    ASSERT_TRUE(d.is_ok()) << d.status().to_string();
    auto out = (*d)->detect(cv::Mat(32, 64, CV_8UC3, cv::Scalar(50, 50, 50)));
    ASSERT_TRUE(out.is_ok()) << out.status().to_string();
    ASSERT_EQ(out->size(), 1u);  // 1024 identical boxes merged by NMS
    EXPECT_EQ((*out)[0].class_name, "car");
    EXPECT_NEAR((*out)[0].score, 0.9f, 1e-5f);
    // net centre (16, 16), 10x12 -> image centre (32, 16), 20x24.
    expect_box_near((*out)[0].box, {22, 4, 20, 24}, 0.5f);
}

TEST(DetectOnnxTest, GarbageAndMissingFilesAreErrors) {
    TempDir dir;
    std::ofstream(dir / "garbage.onnx") << "this is not a protobuf";
    auto d = open_detector(tiny_config(ModelKind::kOnnx, dir / "garbage.onnx"));
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(d.status().message().find(dir / "garbage.onnx"), std::string::npos)
        << d.status().message();
    d = open_detector(tiny_config(ModelKind::kOnnx, dir / "none.onnx"));
    ASSERT_FALSE(d.is_ok());
    EXPECT_EQ(d.status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace df::detect
