// Every option is checked against the range its .proto declares: each kind of rule, the field's
// path in the message, defaults that satisfy their own ranges, and the loader's file errors.
#include "config/validate.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/text_format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "capture.pb.h"
#include "config/config_loader.hpp"
#include "detector.pb.h"
#include "fusion.pb.h"
#include "geoseg.pb.h"
#include "slam.pb.h"
#include "slam_system/slam_params.hpp"
#include "slam_system/system_config.hpp"
#include "temp_folder.hpp"

namespace df::config {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

/// Parses `text` into a fresh T and checks it; the error message, or "" when it passes.
template <typename T>
std::string check_text(const std::string& text) {
    T message;
    EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &message)) << text;
    const Status s = check(message);
    return s ? "" : s.message();
}

TEST(Validate, ExclusiveAndInclusiveBoundsAndTheUnit) {
    EXPECT_EQ(check_text<CaptureConfig>("rate: 0"),
              "rate is 0, allowed: > 0 and <= 1000 (unit: x)");
    EXPECT_EQ(check_text<CaptureConfig>("rate: -5"),
              "rate is -5, allowed: > 0 and <= 1000 (unit: x)");
    EXPECT_EQ(check_text<CaptureConfig>("rate: 1000"), "");
    EXPECT_EQ(check_text<CaptureConfig>("rate: 1000.5"),
              "rate is 1000.5, allowed: > 0 and <= 1000 (unit: x)");
    EXPECT_EQ(check_text<CaptureConfig>("start_wait_s: 0"), "");  // inclusive minimum
    EXPECT_EQ(check_text<CaptureConfig>("color_small_jpeg_quality: 1000"),
              "color_small_jpeg_quality is 1000, allowed: >= 1 and <= 100");
}

TEST(Validate, NanAndInfinityAreRefusedForEveryFloat) {
    EXPECT_EQ(check_text<CaptureConfig>("rate: nan"),
              "rate is nan, allowed: > 0 and <= 1000 (unit: x)");
    EXPECT_EQ(check_text<CaptureConfig>("fx: -inf"),
              "fx is -inf, allowed: > 0 and <= 100000 (unit: px)");
    EXPECT_EQ(check_text<FusionServiceConfig>("detection_deadline_ms: nan"),
              "detection_deadline_ms is nan, allowed: >= 0 and <= 600000 (unit: ms)");
    // A float with no declared range still has to be finite: a map value.
    const std::string m =
        check_text<DetectorServiceConfig>("class_score_thresholds { key: 'person' value: nan }");
    EXPECT_EQ(m, "class_score_thresholds[person].value is nan, allowed: finite");
}

TEST(Validate, NestedFieldsAreNamedByTheirPath) {
    EXPECT_EQ(check_text<SlamServiceConfig>("slam { map { confidence_sigma: 0 } }"),
              "slam.map.confidence_sigma is 0, allowed: > 0 and <= 100");
    EXPECT_EQ(check_text<SlamServiceConfig>("slam { map { unstable_max_unseen_frames: -1 } }"),
              "slam.map.unstable_max_unseen_frames is -1, allowed: >= 0 and <= 1000000 (unit: "
              "frames)");
    EXPECT_EQ(check_text<SlamServiceConfig>("slam { prediction { max_splat_radius_px: inf } }"),
              "slam.prediction.max_splat_radius_px is inf, allowed: >= 0 and <= 64 (unit: px)");
    EXPECT_EQ(check_text<SlamServiceConfig>("slam { prediction { threads: -2 } }"),
              "slam.prediction.threads is -2, allowed: >= 0 and <= 256");
    EXPECT_EQ(check_text<SlamServiceConfig>("slam { tracking { iterations: [10, -1, 4] } }"),
              "slam.tracking.iterations[1] is -1, allowed: >= 0 and <= 100");
    EXPECT_EQ(check_text<GeosegServiceConfig>("dds { domain_id: 300 }"),
              "dds.domain_id is 300, allowed: <= 232");
}

TEST(Validate, ChoicesAndNonEmptyStrings) {
    EXPECT_EQ(check_text<DetectorServiceConfig>("dds { ns: '' }"),
              "dds.ns is empty, allowed: not empty");
    EXPECT_EQ(check_text<DetectorServiceConfig>("dds { transport: 'tcp' }"),
              "dds.transport is \"tcp\", allowed: one of auto|shm|shared_memory|udp");
    EXPECT_EQ(check_text<DetectorServiceConfig>("model: 'yolov9'"),
              "model is \"yolov9\", allowed: one of yolov5|darknet|onnx|simulated");
    EXPECT_EQ(check_text<CaptureConfig>("intrinsics_preset: 'FR1'"), "");  // case ignored
    EXPECT_EQ(check_text<CaptureConfig>("lockstep_stages: 'slam' lockstep_stages: ''"),
              "lockstep_stages[1] is empty, allowed: not empty");
    EXPECT_EQ(check_text<SlamServiceConfig>("stage: ''"), "stage is empty, allowed: not empty");
}

TEST(Validate, CrossFieldRulesOfServiceConfigs) {
    EXPECT_EQ(
        check_text<FusionServiceConfig>("classes { rigid: 'cup' rigid: 'book' non_rigid: 'book' }"),
        "class 'book' is listed in both classes.rigid and classes.non_rigid; an instance "
        "is one or the other: remove it from one list");
    EXPECT_EQ(check_text<SlamServiceConfig>("classes { rigid: 'cup' non_rigid: 'cup' }"),
              "class 'cup' is listed in both classes.rigid and classes.non_rigid; an instance "
              "is one or the other: remove it from one list");
    EXPECT_EQ(check_text<DetectorServiceConfig>("input_width: 100"),
              "input_width x input_height is 100x640, allowed: multiples of 32");
    EXPECT_EQ(check_text<DetectorServiceConfig>("input_width: 100000"),
              "input_width is 100000, allowed: >= 32 and <= 2048 (unit: px)");
    EXPECT_EQ(check_text<DetectorServiceConfig>("class_score_thresholds { key: 'dog' value: 2 }"),
              "class_score_thresholds[dog] is 2, allowed: >= 0 and <= 1");
    EXPECT_EQ(check_text<GeosegServiceConfig>("params { neighbours: 6 }"),
              "params.neighbours is 6, allowed: 4 or 8");
    EXPECT_EQ(check_text<CaptureConfig>("width: 640"),
              "width and height go together: found 640x0 (0x0 = the first frame's size)");
}

/// Sets every field that declares a default to that default, nested messages included.
void set_declared_defaults(Message* m) {
    const auto* type = m->GetDescriptor();
    const auto* r = m->GetReflection();
    for (int i = 0; i < type->field_count(); ++i) {
        const FieldDescriptor* f = type->field(i);
        if (f->is_repeated()) continue;
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
            set_declared_defaults(r->MutableMessage(m, f));
            continue;
        }
        if (!f->has_default_value()) continue;
        switch (f->cpp_type()) {
            case FieldDescriptor::CPPTYPE_INT32:
                r->SetInt32(m, f, f->default_value_int32());
                break;
            case FieldDescriptor::CPPTYPE_INT64:
                r->SetInt64(m, f, f->default_value_int64());
                break;
            case FieldDescriptor::CPPTYPE_UINT32:
                r->SetUInt32(m, f, f->default_value_uint32());
                break;
            case FieldDescriptor::CPPTYPE_UINT64:
                r->SetUInt64(m, f, f->default_value_uint64());
                break;
            case FieldDescriptor::CPPTYPE_FLOAT:
                r->SetFloat(m, f, f->default_value_float());
                break;
            case FieldDescriptor::CPPTYPE_DOUBLE:
                r->SetDouble(m, f, f->default_value_double());
                break;
            case FieldDescriptor::CPPTYPE_BOOL:
                r->SetBool(m, f, f->default_value_bool());
                break;
            case FieldDescriptor::CPPTYPE_STRING:
                r->SetString(m, f, f->default_value_string());
                break;
            case FieldDescriptor::CPPTYPE_ENUM:
                r->SetEnum(m, f, f->default_value_enum());
                break;
            default:
                break;
        }
    }
}

TEST(Validate, EveryDeclaredDefaultSatisfiesItsOwnRange) {
    CaptureConfig capture;
    DetectorServiceConfig detector;
    detector.set_model("yolov5");
    FusionServiceConfig fusion;
    GeosegServiceConfig geoseg;
    SlamServiceConfig slam;
    for (Message* m : std::vector<Message*>{&capture, &detector, &fusion, &geoseg, &slam}) {
        set_declared_defaults(m);
        const Status s = check(*m);
        EXPECT_TRUE(s) << m->GetTypeName() << ": " << s.message();
    }
}

TEST(Validate, SlamLibraryDefaultsSatisfyTheRangesOfSlamProto) {
    const SlamParams params = slam::to_params(slam::SystemConfig{});
    // Every parameter of the table made it into the message.
    std::vector<const FieldDescriptor*> sections;
    params.GetReflection()->ListFields(params, &sections);
    // preprocess tracking map prediction system dynamics motion invalid memory objects
    // propagation
    EXPECT_EQ(sections.size(), 11u);
    const Status s = check_fields(params, "slam.");
    EXPECT_TRUE(s) << s.message();
    EXPECT_NE(
        slam::params_table(slam::SystemConfig{})
            .find("map.confidence_sigma                             0.6        > 0 and <= 100"),
        std::string::npos)
        << slam::params_table(slam::SystemConfig{});
}

TEST(Validate, SlamRangeEndsAreAcceptedByTheLibrary) {
    // What slam.proto lets through at start, the library must take too: otherwise the error
    // comes on the first frame instead of at start. Each end of each range is tried alone
    // (exclusive ends just inside), the other parameters at their defaults. Covers the checks
    // of slam::validate (preprocess, tracking, system).
    const auto* top = SlamParams::descriptor();
    for (int s = 0; s < top->field_count(); ++s) {
        const FieldDescriptor* section = top->field(s);
        for (int i = 0; i < section->message_type()->field_count(); ++i) {
            const FieldDescriptor* f = section->message_type()->field(i);
            if (!f->options().HasExtension(range)) continue;
            const Range& r = f->options().GetExtension(range);
            for (int end = 0; end < 2; ++end) {
                if (end == 0 && !r.has_min()) continue;
                if (end == 1 && !r.has_max()) continue;
                double v = end == 0 ? r.min() : r.max();
                const bool exclusive = end == 0 ? r.min_exclusive() : r.max_exclusive();
                const bool integer = f->cpp_type() != FieldDescriptor::CPPTYPE_FLOAT &&
                                     f->cpp_type() != FieldDescriptor::CPPTYPE_DOUBLE;
                if (exclusive) v += (end == 0 ? 1 : -1) * (integer ? 1.0 : 1e-3);
                std::ostringstream value;
                value.precision(10);
                value << v;
                std::string text = section->name() + " { " + f->name() + ": " +
                                   (f->is_repeated() ? "[" + value.str() + "]" : value.str()) +
                                   " }";
                SlamParams params;
                ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &params)) << text;
                if (!check_fields(params, "slam.")) continue;  // e.g. a rounding past the end
                slam::SystemConfig config;
                ASSERT_TRUE(slam::apply(params, &config)) << text;
                const std::string e = slam::validate(config);
                // Rules between two parameters are not ranges: these may refuse one end alone.
                const bool cross_field = e.find("min_depth_m < max_depth_m") != std::string::npos ||
                                         e.find("one per iterations entry") != std::string::npos ||
                                         e.find("levels but") != std::string::npos ||
                                         e.find("levels, tracking.iterations") != std::string::npos;
                if (!cross_field) {
                    EXPECT_EQ(e, "") << text;
                }
            }
        }
    }
}

TEST(Validate, HelpListsEveryFieldWithDefaultAndRange) {
    const std::string help = options_help(CaptureConfig::descriptor());
    EXPECT_NE(help.find("dds.transport"), std::string::npos) << help;
    EXPECT_NE(help.find("one of auto|shm|shared_memory|udp"), std::string::npos) << help;
    EXPECT_NE(help.find("rate                                         1            > 0 and "
                        "<= 1000 [x]"),
              std::string::npos)
        << help;
    EXPECT_EQ(allowed_text(CaptureConfig::descriptor()->FindFieldByName("folder")), "");
    EXPECT_EQ(allowed_text(ClassParams::descriptor()->FindFieldByName("rigid")), "each not empty");
}

TEST(Validate, EveryDeployConfigurationPassesItsChecks) {
    // deploy/config/<service>_*.pbtxt: what `bash deploy/main.sh` starts must not be refused.
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(DF_SOURCE_DIR) / "deploy" / "config";
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".pbtxt") continue;
        const std::string name = entry.path().filename().string();
        std::unique_ptr<Message> m;
        if (name.rfind("capture", 0) == 0) m = std::make_unique<CaptureConfig>();
        if (name.rfind("slam", 0) == 0) m = std::make_unique<SlamServiceConfig>();
        if (name.rfind("detector", 0) == 0) m = std::make_unique<DetectorServiceConfig>();
        if (name.rfind("fusion", 0) == 0) m = std::make_unique<FusionServiceConfig>();
        if (name.rfind("geoseg", 0) == 0) m = std::make_unique<GeosegServiceConfig>();
        if (!m) {
            ADD_FAILURE() << "no configuration type known for " << entry.path();
            continue;
        }
        Status s = load(entry.path().string(), {}, m.get());
        if (s) s = check(*m);
        EXPECT_TRUE(s) << entry.path() << ": " << s.message();
        ++checked;
    }
    EXPECT_GE(checked, 5);
}

TEST(Load, FolderMissingFileAndBadTextNameThePath) {
    test::TempFolder tmp;
    CaptureConfig c;
    Status s = load(tmp.str(), {}, &c);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("'" + tmp.str() + "' is not a regular file"), std::string::npos)
        << s.message();
    s = load(tmp / "none.txt", {}, &c);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find(tmp / "none.txt"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("does not exist"), std::string::npos) << s.message();
    { std::ofstream(tmp / "bad.txt") << "rate: 2\nratte: 3\n"; }
    s = load(tmp / "bad.txt", {}, &c);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find(tmp / "bad.txt" + ":2:"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace df::config
