// Parameter messages onto the structs generated from the same declaration (config/apply_params.hpp,
// params/*.hpp): what a user sets arrives, what they leave out keeps the declared default, and
// the declared ranges are what the libraries enforce.
#include <gtest/gtest.h>
#include <google/protobuf/text_format.h>

#include <limits>

#include "config/apply_params.hpp"
#include "detector.pb.h"
#include "fusion.pb.h"
#include "geoseg.pb.h"
#include "params/detector_params.hpp"
#include "params/fusion_params.hpp"
#include "params/geoseg_params.hpp"

namespace df::config {
namespace {

TEST(ApplyParams, SetFieldsArriveAndTheOthersKeepTheirDeclaredDefaults) {
    GeosegParams message;
    ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(
        "max_concavity: 0.25 min_segment_pixels: 500 neighbours: 8", &message));
    params::geoseg::GeosegParams seg;
    ASSERT_TRUE(apply_params(message, &seg));
    EXPECT_FLOAT_EQ(seg.max_concavity, 0.25f);
    EXPECT_EQ(seg.min_segment_pixels, 500);
    EXPECT_EQ(seg.neighbours, 8);
    // Unset: the default declared in geoseg.proto, which is also what the message reports.
    EXPECT_FLOAT_EQ(seg.max_distance_m, GeosegParams::default_instance().max_distance_m());
    EXPECT_FLOAT_EQ(seg.max_distance_m, 0.01f);
    EXPECT_EQ(seg.absorb_iterations, 2);
}

TEST(ApplyParams, AServiceMessagesMarkedFieldsMakeAStruct) {
    // The detector's thresholds are flat fields of DetectorServiceConfig marked
    // (params_struct) = "DetectorParams"; the struct has those and nothing else.
    DetectorServiceConfig message;
    ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(
        "model: \"simulated\" score_threshold: 0.4 input_width: 320 max_detections: 7", &message));
    params::detector::DetectorParams d;
    ASSERT_TRUE(apply_params(message, &d));
    EXPECT_FLOAT_EQ(d.score_threshold, 0.4f);
    EXPECT_EQ(d.input_width, 320);
    EXPECT_EQ(d.max_detections, 7);
    EXPECT_EQ(d.input_height, 640);  // declared default
    EXPECT_FLOAT_EQ(d.nms_iou_threshold, DetectorServiceConfig::default_instance().nms_iou_threshold());
    int fields = 0;
    d.for_each_field([&](const params::FieldInfo&, const auto&) { ++fields; });
    EXPECT_EQ(fields, 6);  // input_width, input_height, score, nms, threads, max_detections
}

TEST(ApplyParams, TheStructDefaultsAreTheDeclaredOnes) {
    const params::fusion::InstanceParams s;
    const InstanceParams& m = InstanceParams::default_instance();
    EXPECT_FLOAT_EQ(s.min_iou, m.min_iou());
    EXPECT_FLOAT_EQ(s.min_inside_fraction, m.min_inside_fraction());
    EXPECT_FLOAT_EQ(s.max_depth_from_core_m, m.max_depth_from_core_m());
    EXPECT_FLOAT_EQ(s.min_core_box_fraction, m.min_core_box_fraction());
    EXPECT_FLOAT_EQ(s.min_fill_fraction, m.min_fill_fraction());
    EXPECT_EQ(s.min_instance_pixels, m.min_instance_pixels());
    const params::geoseg::GeosegParams g;
    const GeosegParams& gm = GeosegParams::default_instance();
    EXPECT_FLOAT_EQ(g.max_concavity, gm.max_concavity());
    EXPECT_FLOAT_EQ(g.max_depth_m, gm.max_depth_m());
    EXPECT_EQ(g.normal_baseline_px, gm.normal_baseline_px());
}

TEST(ApplyParams, OutOfRangeValuesAreNamedWithTheDeclaredRange) {
    params::fusion::InstanceParams s;
    s.min_instance_pixels = 0;
    EXPECT_EQ(params::check(s), "min_instance_pixels is 0, allowed: >= 1 and <= 307200 [px]");
    s = {};
    s.min_iou = std::numeric_limits<float>::infinity();
    EXPECT_EQ(params::check(s).rfind("min_iou is inf, allowed: > 0 and <= 1", 0), 0u)
        << params::check(s);
    EXPECT_EQ(params::check(params::geoseg::GeosegParams{}), "");
}

}  // namespace
}  // namespace df::config
