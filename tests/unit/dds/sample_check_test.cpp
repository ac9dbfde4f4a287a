// Sample checks at the boundary: a valid sample of each type passes, and each crafted bad field
// is refused with a message naming the field, its value and the limit; the converters refuse
// what the check refuses; repeated identical rejections are logged once per interval.
#include "dds/sample_check.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "dds/msg_convert.hpp"

namespace df::dds {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

template <typename T>
struct BadCase {
    const char* what;
    std::function<void(T&)> spoil;
    std::vector<std::string> expected;  ///< substrings of the message
};

template <typename T>
void expect_refused(const T& good, const std::vector<BadCase<T>>& cases) {
    ASSERT_TRUE(check_sample(good).is_ok()) << check_sample(good).to_string();
    for (const BadCase<T>& c : cases) {
        auto sample = std::make_unique<T>(good);
        c.spoil(*sample);
        const Status s = check_sample(*sample);
        EXPECT_FALSE(s.is_ok()) << c.what << " was accepted";
        EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << c.what;
        for (const std::string& e : c.expected)
            EXPECT_NE(s.message().find(e), std::string::npos)
                << c.what << ": '" << s.message() << "' does not say '" << e << "'";
    }
}

std::unique_ptr<df_msg_RgbdFrame> good_frame() {
    auto f = std::make_unique<df_msg_RgbdFrame>();
    *f = {};
    f->width = 640;
    f->height = 480;
    f->intrinsics = {535.4f, 539.2f, 320.1f, 247.6f};
    f->depth_units_per_m = 5000;
    f->header.seq = 7;
    return f;
}

TEST(SampleCheck, RgbdFrameFields) {
    const auto good = good_frame();
    expect_refused<df_msg_RgbdFrame>(
        *good,
        {
            {"65535x65535",
             [](auto& f) { f.width = f.height = 65535; },
             {"RgbdFrame.width", "65535", "MAX_WIDTH 640"}},
            {"1000x480", [](auto& f) { f.width = 1000; }, {"width 1000 > MAX_WIDTH 640"}},
            {"640x481", [](auto& f) { f.height = 481; }, {"height 481 > MAX_HEIGHT 480"}},
            {"0x480", [](auto& f) { f.width = 0; }, {"0x480", "empty"}},
            {"status 7",
             [](auto& f) { f.header.status = static_cast<df_msg_FrameStatus>(7); },
             {"header.status 7", "FrameStatus"}},
            {"status -1",
             [](auto& f) { f.header.status = static_cast<df_msg_FrameStatus>(-1); },
             {"header.status -1"}},
            {"fx 0", [](auto& f) { f.intrinsics.fx = 0; }, {"intrinsics.fx 0"}},
            {"fx -1", [](auto& f) { f.intrinsics.fx = -1; }, {"intrinsics.fx -1"}},
            {"fx NaN", [](auto& f) { f.intrinsics.fx = kNaN; }, {"intrinsics.fx nan"}},
            {"fy inf", [](auto& f) { f.intrinsics.fy = kInf; }, {"intrinsics.fy inf"}},
            {"fy 1e30", [](auto& f) { f.intrinsics.fy = 1e30f; }, {"intrinsics.fy", "100000"}},
            {"cx NaN", [](auto& f) { f.intrinsics.cx = kNaN; }, {"intrinsics.cx nan"}},
            {"cx 1e30", [](auto& f) { f.intrinsics.cx = 1e30f; }, {"intrinsics.cx", "640"}},
            {"cy -5", [](auto& f) { f.intrinsics.cy = -5; }, {"intrinsics.cy -5", "480"}},
            {"units 0", [](auto& f) { f.depth_units_per_m = 0; }, {"depth_units_per_m 0"}},
            {"units -5000",
             [](auto& f) { f.depth_units_per_m = -5000; },
             {"depth_units_per_m -5000"}},
            {"units NaN", [](auto& f) { f.depth_units_per_m = kNaN; }, {"depth_units_per_m nan"}},
        });
}

TEST(SampleCheck, ConvertersTakeOnlyCheckedFrames) {
    auto f = good_frame();
    f->width = 4;
    f->height = 2;
    f->intrinsics.cx = 2;
    f->intrinsics.cy = 1;
    for (int i = 0; i < 8; ++i) f->depth[i] = static_cast<uint16_t>(100 + i);
    auto image = to_image(*f);
    ASSERT_TRUE(image) << image.status().to_string();
    EXPECT_EQ(image->depth.cols, 4);
    EXPECT_EQ(image->depth.rows, 2);
    EXPECT_EQ(image->depth.at<uint16_t>(1, 3), 107);

    f->width = 65535;
    f->height = 65535;
    auto refused = to_image(*f);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.status().message().find("width 65535 > MAX_WIDTH 640"), std::string::npos);
    EXPECT_FALSE(checked(*f));
}

TEST(SampleCheck, GeometricSegmentsLabelsWithinCount) {
    auto good = std::make_unique<df_msg_GeometricSegments>();
    *good = {};
    good->width = 640;
    good->height = 480;
    good->segment_count = 3;
    good->labels[0] = 3;
    good->labels[640 * 480 - 1] = 2;
    expect_refused<df_msg_GeometricSegments>(
        *good, {
                   {"1000x480", [](auto& g) { g.width = 1000; }, {"width 1000 > MAX_WIDTH 640"}},
                   {"count",
                    [](auto& g) { g.segment_count = 400000; },
                    {"segment_count 400000 > MAX_PIXELS 307200"}},
                   {"label",
                    [](auto& g) { g.labels[307199] = 4; },
                    {"labels[307199] 4 > segment_count 3"}},
                   {"status",
                    [](auto& g) { g.header.status = static_cast<df_msg_FrameStatus>(3); },
                    {"header.status 3"}},
               });
    // Labels past width x height are not the sample's: not checked.
    good->width = 10;
    good->height = 10;
    good->labels[100] = 9;
    EXPECT_TRUE(check_sample(*good).is_ok());
}

TEST(SampleCheck, ObjectSegmentsInstancesAndLabels) {
    auto good = std::make_unique<df_msg_ObjectSegments>();
    *good = {};
    good->width = 320;
    good->height = 240;
    good->instance_count = 2;
    good->instances[0] = {5, 0, 0.9f, df_msg_OBJECT_NON_RIGID, 10, 20, 30, 40, 100, 0};
    good->instances[1] = {9, 56, 0.5f, df_msg_OBJECT_RIGID, 0, 0, 5, 5, 25, 3};
    good->labels[0] = 5;
    good->labels[320 * 240 - 1] = 9;
    expect_refused<df_msg_ObjectSegments>(
        *good,
        {
            {"instance_count",
             [](auto& s) { s.instance_count = 65; },
             {"instance_count 65 > MAX_INSTANCES 64"}},
            {"label of no instance",
             [](auto& s) { s.labels[1000] = 6; },
             {"labels[1000] 6", "no instance_id"}},
            {"label of a cut instance", [](auto& s) { s.instance_count = 1; }, {"labels[76799] 9"}},
            {"id 0",
             [](auto& s) { s.instances[1].instance_id = 0; },
             {"instances[1].instance_id 0"}},
            {"id repeated",
             [](auto& s) { s.instances[1].instance_id = 5; },
             {"instances[1].instance_id 5 repeated"}},
            {"class 80",
             [](auto& s) { s.instances[0].class_id = 80; },
             {"instances[0].class_id 80"}},
            {"class -2",
             [](auto& s) { s.instances[0].class_id = -2; },
             {"instances[0].class_id -2"}},
            {"score NaN", [](auto& s) { s.instances[1].score = kNaN; }, {"instances[1].score nan"}},
            {"score 2", [](auto& s) { s.instances[1].score = 2; }, {"instances[1].score 2"}},
            {"kind 9",
             [](auto& s) { s.instances[0].kind = static_cast<df_msg_ObjectKind>(9); },
             {"instances[0].kind 9", "ObjectKind"}},
            {"box inf", [](auto& s) { s.instances[0].box_x = kInf; }, {"instances[0].box.x inf"}},
            {"box w < 0", [](auto& s) { s.instances[0].box_w = -1; }, {"instances[0].box.w -1"}},
            {"pixel_count",
             [](auto& s) { s.instances[0].pixel_count = 76801; },
             {"instances[0].pixel_count 76801 > width x height 76800"}},
            {"65535 wide", [](auto& s) { s.width = 65535; }, {"width 65535 > MAX_WIDTH"}},
            {"boolean 2",
             [](auto& s) { std::memset(&s.detections_used, 2, 1); },
             {"detections_used 2 not a boolean"}},
        });
}

TEST(SampleCheck, DetectionsCountAndBoxes) {
    df_msg_Detections good{};
    good.image_width = 640;
    good.image_height = 480;
    good.count = 2;
    good.boxes[0] = {1, 2, 3, 4, 0, 0.5f};
    good.boxes[1] = {-10, 470, 50, 20, -1, 1.0f};
    expect_refused<df_msg_Detections>(
        good,
        {
            {"count", [](auto& d) { d.count = 129; }, {"count 129 > MAX_DETECTIONS 128"}},
            {"count huge",
             [](auto& d) { d.count = 0xFFFFFFFF; },
             {"count 4294967295 > MAX_DETECTIONS"}},
            {"x NaN", [](auto& d) { d.boxes[1].x = kNaN; }, {"boxes[1].x nan"}},
            {"h inf", [](auto& d) { d.boxes[0].h = kInf; }, {"boxes[0].h inf"}},
            {"y 1e9", [](auto& d) { d.boxes[0].y = 1e9f; }, {"boxes[0].y 1e+09"}},
            {"score -1", [](auto& d) { d.boxes[0].score = -1; }, {"boxes[0].score -1"}},
            {"class 1000", [](auto& d) { d.boxes[1].class_id = 1000; }, {"boxes[1].class_id 1000"}},
        });
    // Boxes past count are not the sample's.
    good.count = 1;
    good.boxes[1].x = kNaN;
    EXPECT_TRUE(check_sample(good).is_ok());
}

TEST(SampleCheck, CompressedImageFormatSizesAndHeader) {
    const cv::Mat bgr(30, 40, CV_8UC3, cv::Scalar(10, 200, 30));
    std::vector<uint8_t> jpeg, png;
    ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg));
    ASSERT_TRUE(cv::imencode(".png", bgr, png));
    df_msg_CompressedImage good{};
    good.width = 40;
    good.height = 30;
    good.source_width = 640;
    good.source_height = 480;
    std::snprintf(good.format, sizeof(good.format), "jpeg");
    good.data._buffer = jpeg.data();
    good.data._length = good.data._maximum = static_cast<uint32_t>(jpeg.size());
    expect_refused<df_msg_CompressedImage>(
        good,
        {
            {"length",
             [](auto& c) { c.data._length = 921601; },
             {"data length 921601 > MAX_RGB_BYTES 921600"}},
            {"no buffer", [](auto& c) { c.data._buffer = nullptr; }, {"no buffer"}},
            {"format",
             [](auto& c) { std::snprintf(c.format, sizeof(c.format), "bmp"); },
             {"format 'bmp'"}},
            {"format not terminated",
             [](auto& c) { std::memset(c.format, 'j', 8); },
             {"format 'jjjjjjjj'"}},
            {"png bytes said jpeg",
             [&](auto& c) { c.data._buffer = png.data(); },
             {"no jpeg header"}},
            {"size mismatch", [](auto& c) { c.width = 41; }, {"data is a 40x30 jpeg", "41x30"}},
            {"width 1000", [](auto& c) { c.width = 1000; }, {"width 1000 > MAX_WIDTH 640"}},
            {"source 0", [](auto& c) { c.source_height = 0; }, {"640x0 is empty"}},
            {"truncated", [](auto& c) { c.data._length = 3; }, {"(3 bytes) has no jpeg header"}},
        });
    df_msg_CompressedImage as_png = good;
    std::snprintf(as_png.format, sizeof(as_png.format), "png");
    as_png.data._buffer = png.data();
    as_png.data._length = static_cast<uint32_t>(png.size());
    EXPECT_TRUE(check_sample(as_png).is_ok()) << check_sample(as_png).to_string();
    as_png.height = 31;
    EXPECT_NE(check_sample(as_png).message().find("data is a 40x30 png"), std::string::npos);
    // A skipped answer carries no image.
    df_msg_CompressedImage skipped{};
    skipped.header.status = df_msg_FRAME_SKIPPED;
    EXPECT_TRUE(check_sample(skipped).is_ok());
}

TEST(SampleCheck, PosesAndStatus) {
    df_msg_CameraPose pose{};
    pose.world_T_camera.qw = 1;
    pose.world_T_camera.tx = 2.5;
    expect_refused<df_msg_CameraPose>(
        pose,
        {
            {"NaN t",
             [](auto& p) { p.world_T_camera.ty = std::nan(""); },
             {"world_T_camera.ty nan"}},
            {"inf q", [](auto& p) { p.world_T_camera.qx = INFINITY; }, {"world_T_camera.qx inf"}},
            {"not unit", [](auto& p) { p.world_T_camera.qw = 0.5; }, {"quaternion norm 0.5"}},
            {"state",
             [](auto& p) { p.state = static_cast<df_msg_TrackingState>(3); },
             {"state 3", "TrackingState"}},
        });
    df_msg_ObjectPoses objects{};
    objects.count = 1;
    objects.objects[0].world_T_object.qw = 1;
    expect_refused<df_msg_ObjectPoses>(
        objects, {
                     {"count", [](auto& p) { p.count = 65; }, {"count 65 > MAX_OBJECTS 64"}},
                     {"NaN",
                      [](auto& p) { p.objects[0].world_T_object.tz = NAN; },
                      {"objects[0].world_T_object.tz nan"}},
                     {"kind",
                      [](auto& p) { p.objects[0].kind = static_cast<df_msg_ObjectKind>(5); },
                      {"objects[0].kind 5"}},
                     {"visible 255",
                      [](auto& p) { std::memset(&p.objects[0].visible, 255, 1); },
                      {"objects[0].visible 255"}},
                 });
    df_msg_StageStatus st{};
    st.timing_count = 2;
    st.timings[1].ms = 3.5f;
    expect_refused<df_msg_StageStatus>(
        st, {
                {"timing_count",
                 [](auto& s) { s.timing_count = 17; },
                 {"timing_count 17 > MAX_STAGE_TIMINGS 16"}},
                {"ms NaN", [](auto& s) { s.timings[1].ms = kNaN; }, {"timings[1].ms nan"}},
                {"status",
                 [](auto& s) { s.header.status = static_cast<df_msg_FrameStatus>(99); },
                 {"header.status 99"}},
            });
}

TEST(SampleCheck, UntypedDispatchMatchesTypedCheck) {
    auto f = good_frame();
    f->width = 1000;
    const TypeInfo* frame_type = find_type("df::msg::RgbdFrame");
    ASSERT_NE(frame_type, nullptr);
    EXPECT_NE(check_sample(*frame_type, f.get()).message().find("width 1000"), std::string::npos);
    df_msg_StageStatus st{};
    st.timing_count = 99;
    EXPECT_NE(
        check_sample(*find_type("df::msg::StageStatus"), &st).message().find("timing_count 99"),
        std::string::npos);
    // Every type of the pipeline has a check.
    for (const TypeInfo& t : all_types()) {
        std::vector<uint8_t> zero(t.descriptor->m_size, 0);
        EXPECT_EQ(check_sample(t, zero.data()).message().find("no sample check"), std::string::npos)
            << t.name;
    }
}

TEST(RejectLog, IdenticalRejectionsLoggedOncePerInterval) {
    RejectLog log(1'000'000'000);
    const Status why = error(StatusCode::kInvalidArgument, "RgbdFrame.width 1000 > MAX_WIDTH 640");
    EXPECT_TRUE(log.report("t/frames", "writer 01", 1, why, 0));
    for (uint64_t seq = 2; seq < 1000; ++seq)
        EXPECT_FALSE(log.report("t/frames", "writer 01", seq, why, 500'000'000));
    // Another writer or another field is a new line.
    EXPECT_TRUE(log.report("t/frames", "writer 02", 5, why, 500'000'000));
    EXPECT_TRUE(log.report("t/frames", "writer 01", 5,
                           error(StatusCode::kInvalidArgument, "RgbdFrame.height 481"),
                           500'000'000));
    // After the interval the same line again.
    EXPECT_TRUE(log.report("t/frames", "writer 01", 1000, why, 1'000'000'001));
    EXPECT_EQ(log.total(), 1002U);
}

TEST(SampleCheck, LabelScanCostIsSmall) {
    // Figures, not assertions: the label scans are O(pixels); printed for docs/hardening.md.
    auto g = std::make_unique<df_msg_GeometricSegments>();
    *g = {};
    g->width = 640;
    g->height = 480;
    g->segment_count = 100;
    for (size_t i = 0; i < df_msg_MAX_PIXELS; ++i) g->labels[i] = static_cast<uint16_t>(i % 101);
    auto o = std::make_unique<df_msg_ObjectSegments>();
    *o = {};
    o->width = 640;
    o->height = 480;
    o->instance_count = 10;
    for (uint32_t i = 0; i < 10; ++i) o->instances[i].instance_id = static_cast<uint16_t>(i + 1);
    for (size_t i = 0; i < df_msg_MAX_PIXELS; ++i) o->labels[i] = static_cast<uint16_t>(i % 11);
    const int n = 50;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) ASSERT_TRUE(check_sample(*g).is_ok());
    const auto t1 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) ASSERT_TRUE(check_sample(*o).is_ok());
    const auto t2 = std::chrono::steady_clock::now();
    const auto ms = [n](auto d) {
        return std::chrono::duration<double, std::milli>(d).count() / n;
    };
    std::printf("check_sample 640x480: GeometricSegments %.3f ms, ObjectSegments %.3f ms\n",
                ms(t1 - t0), ms(t2 - t1));
}

}  // namespace
}  // namespace df::dds
