// Every SLAM parameter is settable by name from a service configuration (slam.proto), with
// clear errors for bad values.
#include <gtest/gtest.h>
#include <google/protobuf/text_format.h>

#include <limits>
#include <variant>

#include "options.pb.h"

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

// Each parameter is declared once, in slam.proto; the structs are generated from it. The proto's
// default is the struct's default and its range is what the libraries' validate() enforce.
TEST(SlamParameters, TheStructDefaultIsTheProtoDefault) {
    SystemConfig config;
    int compared = 0;
    for (const Parameter& p : parameters(&config)) {
        const google::protobuf::Descriptor* d = config::SlamParams::descriptor();
        const google::protobuf::FieldDescriptor* f = nullptr;
        std::string rest = p.name;
        for (size_t dot; (dot = rest.find('.')) != std::string::npos; rest.erase(0, dot + 1)) {
            f = d->FindFieldByName(rest.substr(0, dot));
            ASSERT_NE(f, nullptr) << p.name;
            d = f->message_type();
        }
        f = d->FindFieldByName(rest);
        ASSERT_NE(f, nullptr) << p.name;
        if (f->is_repeated()) {
            ASSERT_TRUE(f->options().HasExtension(config::defaults)) << p.name;
            EXPECT_EQ(value_text(p), f->options().GetExtension(config::defaults)) << p.name;
        } else {
            ASSERT_TRUE(f->has_default_value()) << p.name;
            using FD = google::protobuf::FieldDescriptor;
            std::visit(
                [&](auto* v) {
                    using T = std::remove_pointer_t<decltype(v)>;
                    if constexpr (std::is_same_v<T, bool>) {
                        EXPECT_EQ(*v, f->default_value_bool()) << p.name;
                    } else if constexpr (std::is_arithmetic_v<T>) {
                        double declared = 0;
                        switch (f->cpp_type()) {
                            case FD::CPPTYPE_FLOAT: declared = f->default_value_float(); break;
                            case FD::CPPTYPE_DOUBLE: declared = f->default_value_double(); break;
                            case FD::CPPTYPE_INT32: declared = f->default_value_int32(); break;
                            case FD::CPPTYPE_UINT64:
                                declared = static_cast<double>(f->default_value_uint64());
                                break;
                            default: ADD_FAILURE() << p.name << ": unexpected type";
                        }
                        EXPECT_EQ(static_cast<double>(*v), declared) << p.name;
                    } else {
                        ADD_FAILURE() << p.name << ": a list without repeated";
                    }
                },
                p.value);
        }
        EXPECT_FALSE(f->options().GetExtension(config::doc).empty()) << p.name << " has no (doc)";
        EXPECT_EQ(p.meaning, f->options().GetExtension(config::doc)) << p.name;
        ++compared;
    }
    EXPECT_GE(compared, 100);
}

TEST(SlamParameters, OutOfRangeValuesAreNamedWithTheDeclaredRange) {
    SystemConfig config;
    config.map.confidence_sigma = 0.f;
    EXPECT_EQ(validate(config), "map.confidence_sigma is 0, allowed: > 0 and <= 100");
    config = SystemConfig{};
    config.objects.association.min_overlap = 1.5f;
    EXPECT_EQ(validate(config), "objects.association.min_overlap is 1.5, allowed: > 0 and <= 1");
    config = SystemConfig{};
    config.tracking.pixel_step = {1, 0, 1};
    EXPECT_EQ(validate(config), "tracking.pixel_step[1] is 0, allowed: >= 1 and <= 16 [px]");
    config = SystemConfig{};
    config.dynamics.motion.max_residual_m = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(validate(config).rfind("motion.max_residual_m is nan, allowed: > 0", 0), 0u)
        << validate(config);
    // Text configs go through the same generated structs, nested sections included.
    config::SlamParams params;
    ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(
        "objects { association { min_overlap: 0.45 class_must_agree: false } max_objects: 3 }",
        &params));
    config = SystemConfig{};
    ASSERT_TRUE(apply(params, &config).is_ok());
    EXPECT_FLOAT_EQ(config.objects.association.min_overlap, 0.45f);
    EXPECT_FALSE(config.objects.association.class_must_agree);
    EXPECT_EQ(config.objects.max_objects, 3);
    const config::SlamParams back = to_params(config);
    EXPECT_FLOAT_EQ(back.objects().association().min_overlap(), 0.45f);
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
