// Every SLAM parameter is settable by name from a service configuration (slam.proto), with
// clear errors for bad values.
#include <gtest/gtest.h>
#include <google/protobuf/text_format.h>

#include "slam_system/parameters.hpp"
#include "slam_system/slam_params.hpp"
#include "slam_system/slam_system.hpp"

namespace df::slam {
namespace {

TEST(SlamParameters, ProtoAndTableListTheSameParameters) {
    const std::vector<std::string> mismatches = slam::mismatches();
    for (const std::string& m : mismatches) ADD_FAILURE() << m;
    SystemConfig config;
    EXPECT_GE(parameters(&config).size(), 40u);
}

TEST(SlamParameters, ConfigTextSetsTheStructFields) {
    config::SlamParams params;
    ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(
        "tracking { icp_max_distance_m: 0.2 iterations: [4, 3, 2] use_rgb: false }"
        " map { max_surfels: 1234 } system { processing_downscale: 1 }"
        " preprocess { max_depth_m: 4.5 }",
        &params));
    SystemConfig config;
    ASSERT_TRUE(apply(params, &config).is_ok());
    EXPECT_FLOAT_EQ(config.tracking.icp_max_distance_m, 0.2f);
    EXPECT_EQ(config.tracking.iterations, (std::vector<int>{4, 3, 2}));
    EXPECT_FALSE(config.tracking.use_rgb);
    EXPECT_EQ(config.map.max_surfels, 1234u);
    EXPECT_EQ(config.system.processing_downscale, 1);
    EXPECT_FLOAT_EQ(config.preprocess.max_depth_m, 4.5f);
    // Untouched fields keep the library defaults.
    EXPECT_FLOAT_EQ(config.tracking.icp_weight, TrackingConfig{}.icp_weight);
}

TEST(SlamParameters, EveryParameterRoundTripsThroughText) {
    SystemConfig config;
    const std::string before = describe(config);
    SystemConfig copy;
    std::vector<Parameter> from = parameters(&config);
    std::vector<Parameter> to = parameters(&copy);
    ASSERT_EQ(from.size(), to.size());
    for (size_t i = 0; i < from.size(); ++i) {
        ASSERT_TRUE(set_value(to[i], value_text(from[i])).is_ok()) << from[i].name;
    }
    EXPECT_EQ(describe(copy), before);
}

TEST(SlamParameters, BadValuesAreRejectedByName) {
    SystemConfig config;
    for (Parameter& p : parameters(&config)) {
        if (p.name == "tracking.icp_max_distance_m") {
            const Status s = set_value(p, "ten");
            EXPECT_FALSE(s.is_ok());
            EXPECT_NE(s.message().find("tracking.icp_max_distance_m"), std::string::npos);
        }
    }
    config = SystemConfig{};
    config.system.processing_downscale = 3;
    auto system = SlamSystem::create(config);
    ASSERT_FALSE(system.is_ok());
    EXPECT_NE(system.status().message().find("processing_downscale"), std::string::npos);
    config = SystemConfig{};
    config.tracking.iterations = {10, 5, 4, 2};
    config.tracking.pixel_step = {1, 1, 1, 1};
    config.tracking.rgb_min_gradient = {5, 3, 1, 1};
    system = SlamSystem::create(config);
    ASSERT_FALSE(system.is_ok());
    EXPECT_NE(system.status().message().find("pyramid_levels"), std::string::npos);
}

TEST(SlamSystemInput, BadImagesAreErrorsAndDoNotChangeTheSystem) {
    auto system = SlamSystem::create(SystemConfig{});
    ASSERT_TRUE(system.is_ok());
    io::RgbdImage image;
    image.depth = cv::Mat(480, 640, CV_16UC1, cv::Scalar(5000));
    image.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(100, 100, 100));
    io::RgbdImage empty;
    EXPECT_FALSE(system->process(empty).is_ok());
    EXPECT_EQ(system->frames(), 0u);
    io::RgbdImage wrong_type = image;
    wrong_type.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(1.f));
    auto r = system->process(wrong_type);
    EXPECT_FALSE(r.is_ok());
    EXPECT_EQ(system->frames(), 0u);
    ASSERT_TRUE(system->process(image).is_ok());
    io::RgbdImage smaller = image;
    smaller.depth = cv::Mat(240, 320, CV_16UC1, cv::Scalar(5000));
    smaller.rgb = cv::Mat(240, 320, CV_8UC3);
    r = system->process(smaller);
    ASSERT_FALSE(r.is_ok());
    EXPECT_NE(r.status().message().find("differs from the first frame"), std::string::npos);
    EXPECT_EQ(system->frames(), 1u);
    // Segments that do not fit the frame are named and not used; the frame is still tracked.
    dynamics::FrameSegments wrong_size;
    wrong_size.objects = dynamics::from_labels(cv::Mat(10, 10, CV_16UC1, cv::Scalar(1)),
                                               dynamics::ObjectKind::kNonRigid);
    r = system->process(image, wrong_size);
    ASSERT_TRUE(r.is_ok()) << r.status().message();
    EXPECT_NE(r->segments_error.find("frame 1: object label image is CV_16UC1 10x10, the frame "
                                     "640x480"),
              std::string::npos)
        << r->segments_error;
    EXPECT_EQ(system->frames(), 2u);  // processed (a flat, textureless wall: tracked as lost)
    dynamics::FrameSegments unknown_id;
    unknown_id.objects.labels = cv::Mat::zeros(480, 640, CV_16UC1);
    unknown_id.objects.labels.at<uint16_t>(100, 200) = 7;
    r = system->process(image, unknown_id);
    ASSERT_TRUE(r.is_ok()) << r.status().message();
    EXPECT_NE(r->segments_error.find("frame 2: object label 7 at pixel (200, 100) is not in the "
                                     "instance table"),
              std::string::npos)
        << r->segments_error;
    EXPECT_EQ(system->frames(), 3u);
}

}  // namespace
}  // namespace df::slam
