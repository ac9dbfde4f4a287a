// Motion segmentation on synthetic residual images whose answer is known: a moving box over a
// static scene with sensor-like noise, a static scene alone, a mover that pauses, and bad input.
#include "dynamics/motion_segmentation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace df::dynamics {
namespace {

constexpr int kW = 160, kH = 120;

struct Scene {
    cv::Mat residual, depth, geometric, truth;
    int segments = 0;
};

/// A static wall at 2 m with residual noise (sigma 4 mm) and, when `moving`, a 40x30 box whose
/// residual is `box_residual_m`. Geometric segments: the wall split in 4 quadrants, the box its
/// own segment (id 5).
Scene make_scene(bool moving, float box_residual_m, uint32_t seed) {
    Scene s;
    s.residual.create(kH, kW, CV_32F);
    s.depth = cv::Mat(kH, kW, CV_32F, cv::Scalar(2.f));
    s.geometric.create(kH, kW, CV_32S);
    s.truth = cv::Mat::zeros(kH, kW, CV_8UC1);
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.f, 0.004f);
    const cv::Rect box(60, 40, 40, 30);
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            const bool in_box = box.contains(cv::Point(x, y));
            s.geometric.at<int>(y, x) = in_box ? 5 : 1 + (x >= kW / 2) + 2 * (y >= kH / 2);
            float r = noise(rng);
            if (moving && in_box) {
                r = -box_residual_m + noise(rng);
                s.truth.at<uint8_t>(y, x) = 255;
            }
            s.residual.at<float>(y, x) = r;
        }
    }
    s.segments = 5;
    return s;
}

double iou(const cv::Mat& a, const cv::Mat& b) {
    const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
    return uni > 0 ? inter / uni : 1.0;
}

MotionInput input_of(const Scene& s) {
    MotionInput in;
    in.residual_m = s.residual;
    in.depth_m = s.depth;
    in.geometric = s.geometric;
    in.geometric_count = s.segments;
    return in;
}

TEST(MotionSegmentation, FindsTheMovingBoxAsAWholeSegment) {
    const Scene s = make_scene(true, 0.15f, 1);
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    auto r = segment_motion(input_of(s), c);
    ASSERT_TRUE(r.is_ok()) << r.status().message();
    EXPECT_TRUE(r->moving);
    EXPECT_EQ(r->segments, 1);
    EXPECT_GT(iou(r->mask, s.truth), 0.99);
    EXPECT_GT(r->clusters.high - r->clusters.low, 0.1f);
}

TEST(MotionSegmentation, GrowsOverTheSegmentWherePartOfItHasNoResidual) {
    Scene s = make_scene(true, 0.15f, 2);
    // A third of the box has no model behind it (NaN): the segment still goes whole.
    for (int y = 40; y < 50; ++y)
        for (int x = 60; x < 100; ++x)
            s.residual.at<float>(y, x) = std::numeric_limits<float>::quiet_NaN();
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    auto r = segment_motion(input_of(s), c);
    ASSERT_TRUE(r.is_ok());
    EXPECT_GT(iou(r->mask, s.truth), 0.99);
}

TEST(MotionSegmentation, AStaticSceneFlagsNothing) {
    for (uint32_t seed = 1; seed <= 5; ++seed) {
        const Scene s = make_scene(false, 0.f, seed);
        auto r = segment_motion(input_of(s), MotionSegmentationConfig{});
        ASSERT_TRUE(r.is_ok());
        EXPECT_FALSE(r->moving) << "seed " << seed;
        EXPECT_EQ(cv::countNonZero(r->mask), 0) << "seed " << seed;
    }
}

TEST(MotionSegmentation, WithoutSegmentsKeepsLargeRegionsOnly) {
    Scene s = make_scene(true, 0.15f, 3);
    // Ten isolated outliers (flying pixels) are no mover.
    for (int k = 0; k < 10; ++k) s.residual.at<float>(5 + k * 3, 5) = 0.2f;
    MotionInput in = input_of(s);
    in.geometric = cv::Mat();
    in.geometric_count = 0;
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    auto r = segment_motion(in, c);
    ASSERT_TRUE(r.is_ok());
    EXPECT_EQ(r->segments, 1);
    EXPECT_GT(iou(r->mask, s.truth), 0.95);
    EXPECT_EQ(r->mask.at<uint8_t>(5, 5), 0);
}

TEST(MotionSegmentation, ExcludedPixelsAreNeitherClusteredNorFlagged) {
    const Scene s = make_scene(true, 0.15f, 4);
    MotionInput in = input_of(s);
    in.excluded = s.truth.clone();  // the box is already an instance
    auto r = segment_motion(in, MotionSegmentationConfig{});
    ASSERT_TRUE(r.is_ok());
    EXPECT_FALSE(r->moving);
    EXPECT_EQ(cv::countNonZero(r->mask & s.truth), 0);
}

/// The box barely moves this frame: only a fifth of it is above the noise floor.
Scene slowing_box() {
    Scene s = make_scene(true, 0.15f, 5);
    for (int y = 40; y < 70; ++y)
        for (int x = 60; x < 92; ++x) s.residual.at<float>(y, x) = -0.01f;
    return s;
}

TEST(MotionSegmentation, AMoverThatSlowsDownStaysDynamicWhenCarriedForward) {
    const Scene s = slowing_box();
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    auto alone = segment_motion(input_of(s), c);
    ASSERT_TRUE(alone.is_ok());
    EXPECT_EQ(cv::countNonZero(alone->mask & s.truth), 0) << "a fifth is too little evidence";
    MotionInput in = input_of(s);
    in.carried = s.truth.clone();  // it was dynamic in the previous frame
    auto carried = segment_motion(in, c);
    ASSERT_TRUE(carried.is_ok());
    EXPECT_GT(iou(carried->mask, s.truth), 0.99);
}

TEST(MotionSegmentation, ATexturedObjectTurningInPlaceIsFoundByItsIntensityChange) {
    // A rolling drum keeps its shape: only its leading edge (40 px) has a geometric residual,
    // but its texture changes everywhere on it.
    Scene s = make_scene(true, 0.15f, 7);
    for (int y = 40; y < 70; ++y)
        for (int x = 60; x < 100; ++x)
            if (!(y < 42 && x < 80)) s.residual.at<float>(y, x) = 0.002f;
    cv::Mat photometric(kH, kW, CV_32F, cv::Scalar(2.f));
    photometric.setTo(2.f);
    photometric.setTo(80.f, s.truth);
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    MotionInput in = input_of(s);
    auto without = segment_motion(in, c);
    ASSERT_TRUE(without.is_ok());
    EXPECT_EQ(cv::countNonZero(without->mask & s.truth), 0);
    in.photometric = photometric;
    auto with = segment_motion(in, c);
    ASSERT_TRUE(with.is_ok());
    EXPECT_GT(iou(with->mask, s.truth), 0.99);
    // Intensity change alone (no geometric evidence at all) makes nothing dynamic.
    const Scene still = make_scene(false, 0.f, 8);
    MotionInput only_photo = input_of(still);
    only_photo.photometric = photometric;
    auto none = segment_motion(only_photo, c);
    ASSERT_TRUE(none.is_ok());
    EXPECT_EQ(cv::countNonZero(none->mask), 0);
}

TEST(MotionSegmentation, IntensityChangeOnAFrameWhoseColourIsOffEverywhereIsNoEvidence) {
    // The drum of the test above, seen by a camera whose colour differs from the model by 40
    // levels over the whole frame (exposure drift, colour not registered to depth): its change
    // of 80 levels is then within the frame's own spread, and the leading edge alone is too
    // little evidence; the same drum on a clean frame is found.
    Scene s = make_scene(true, 0.15f, 7);
    for (int y = 40; y < 70; ++y)
        for (int x = 60; x < 100; ++x)
            if (!(y < 42 && x < 80)) s.residual.at<float>(y, x) = 0.002f;
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    MotionInput in = input_of(s);
    cv::Mat off_everywhere(kH, kW, CV_32F, cv::Scalar(40.f));
    off_everywhere.setTo(80.f, s.truth);
    in.photometric = off_everywhere;
    auto drifted = segment_motion(in, c);
    ASSERT_TRUE(drifted.is_ok());
    EXPECT_EQ(cv::countNonZero(drifted->mask & s.truth), 0);
    EXPECT_FLOAT_EQ(drifted->photometric_threshold, 5.f * 40.5f);
    // The fixed threshold alone (spread factor 0) would have taken it.
    c.photometric_spread_factor = 0.f;
    auto fixed = segment_motion(in, c);
    ASSERT_TRUE(fixed.is_ok());
    EXPECT_GT(iou(fixed->mask, s.truth), 0.99);
    c.photometric_spread_factor = 5.f;
    cv::Mat clean(kH, kW, CV_32F, cv::Scalar(3.f));
    clean.setTo(80.f, s.truth);
    in.photometric = clean;
    auto found = segment_motion(in, c);
    ASSERT_TRUE(found.is_ok());
    EXPECT_FLOAT_EQ(found->photometric_threshold, c.min_photometric);
    EXPECT_GT(iou(found->mask, s.truth), 0.99);
}

TEST(MotionSegmentation, AFarMoverNoSegmentHoldsIsFoundAsARegionGrownOverItsWeakerPixels) {
    // A small thing at 4 m that the geometric segmentation left unlabelled (its segments fell
    // under the minimum size): 0 in the segment image. At 4 m the noise floor is 0.11 m; half
    // of its pixels (a checkerboard) are above it, the other half at 0.1 m, above
    // region_grow_fraction (0.85) of the floor, but not the floor itself.
    Scene s = make_scene(true, 0.15f, 9);
    const cv::Rect box(60, 40, 40, 30);
    for (int y = box.y; y < box.y + box.height; ++y) {
        for (int x = box.x; x < box.x + box.width; ++x) {
            s.geometric.at<int>(y, x) = 0;
            s.depth.at<float>(y, x) = 4.f;
            s.residual.at<float>(y, x) = ((x + y) % 2 == 0) ? 0.15f : 0.1f;
        }
    }
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    auto grown = segment_motion(input_of(s), c);
    ASSERT_TRUE(grown.is_ok()) << grown.status().message();
    EXPECT_EQ(grown->segments, 1);
    EXPECT_GT(iou(grown->mask, s.truth), 0.99);
    // Without growing, only the pixels above the floor: half of it.
    c.region_grow_fraction = 1.f;
    auto strong_only = segment_motion(input_of(s), c);
    ASSERT_TRUE(strong_only.is_ok());
    EXPECT_NEAR(iou(strong_only->mask, s.truth), 0.5, 0.02);
    // Too few dynamic pixels for a region: nothing.
    c.region_grow_fraction = MotionSegmentationConfig{}.region_grow_fraction;
    c.min_region_pixels = 700;
    auto too_small = segment_motion(input_of(s), c);
    ASSERT_TRUE(too_small.is_ok());
    EXPECT_EQ(cv::countNonZero(too_small->mask), 0);
}

TEST(MotionSegmentation, WarpMaskFollowsTheCameraMotion) {
    // A fronto-parallel plane at 2 m; the camera moved 0.1 m to the right, so a point seen at
    // pixel u before is at u - f * 0.1 / 2 now.
    const float f = 100.f, cx = 80.f, cy = 60.f;
    cv::Mat vertex(kH, kW, CV_32FC3);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            vertex.at<cv::Vec3f>(y, x) = cv::Vec3f((x - cx) * 2.f / f, (y - cy) * 2.f / f, 2.f);
    cv::Mat previous = cv::Mat::zeros(kH, kW, CV_8UC1);
    previous(cv::Rect(70, 50, 20, 20)).setTo(255);
    Eigen::Isometry3f previous_T_current = Eigen::Isometry3f::Identity();
    previous_T_current.translation() = Eigen::Vector3f(0.1f, 0.f, 0.f);
    const cv::Mat warped = warp_mask(previous, vertex, previous_T_current, f, f, cx, cy);
    cv::Mat expected = cv::Mat::zeros(kH, kW, CV_8UC1);
    expected(cv::Rect(65, 50, 20, 20)).setTo(255);
    EXPECT_GT(iou(warped, expected), 0.9);
}

/// The vertex map of a depth image (fx = fy = 100, centre at the image's).
cv::Mat vertex_of(const cv::Mat& depth) {
    cv::Mat vertex(depth.size(), CV_32FC3);
    for (int y = 0; y < depth.rows; ++y)
        for (int x = 0; x < depth.cols; ++x) {
            const float z = depth.at<float>(y, x);
            vertex.at<cv::Vec3f>(y, x) =
                cv::Vec3f((x - 80.f) * z / 100.f, (y - 60.f) * z / 100.f, z);
        }
    return vertex;
}

TEST(MotionSegmentation, HistoryEvidenceTellsSeenThroughFromSeenThereFromOccluded) {
    // A wall at 2 m; the camera moved 0.1 m to the right since the old frame.
    const cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    Eigen::Isometry3f old_T_current = Eigen::Isometry3f::Identity();
    old_T_current.translation() = Eigen::Vector3f(0.1f, 0.f, 0.f);
    const MotionSegmentationConfig c;
    const auto count = [&](float old_z, uint8_t code) {
        const cv::Mat old_depth(kH, kW, CV_32F, cv::Scalar(old_z));
        const cv::Mat h = history_evidence(vertex_of(depth), cv::Mat(), old_depth, cv::Mat(),
                                           old_T_current, 100.f, 100.f, 80.f, 60.f, c);
        return cv::countNonZero(h == code);
    };
    // The point moves 5 px in the image: the last 5 columns project outside the old frame.
    const int inside = (kW - 5) * kH;
    EXPECT_EQ(count(2.01f, kStill), inside);       // the old frame saw the wall there
    EXPECT_EQ(count(2.5f, kMoved), inside);        // it saw 0.5 m farther: through where it is now
    EXPECT_EQ(count(1.5f, kNoEvidence), kW * kH);  // something stood in front: no evidence
    EXPECT_EQ(count(0.f, kNoEvidence), kW * kH);   // no old depth
}

TEST(MotionSegmentation, FreeSpaceFilledIsWhereTheOldFrameSawWellBeyondThePoint) {
    // The current frame sees a wall at 2 m, the camera has not moved.
    const cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    const Eigen::Isometry3f same = Eigen::Isometry3f::Identity();
    const MotionSegmentationConfig c;  // margin 0.05 m + 0.005 z^2: 0.07 m at 2 m
    const auto filled = [&](const cv::Mat& old_depth) {
        return cv::countNonZero(
            free_space_filled(vertex_of(depth), old_depth, same, 100.f, 100.f, 80.f, 60.f, c));
    };
    const int interior = (kW - 2) * (kH - 2);  // the 3x3 neighbourhood must lie in the image
    EXPECT_EQ(filled(cv::Mat(kH, kW, CV_32F, cv::Scalar(2.5f))), interior);  // saw 0.5 m farther
    EXPECT_EQ(filled(cv::Mat(kH, kW, CV_32F, cv::Scalar(2.05f))), 0);  // within the margin
    EXPECT_EQ(filled(cv::Mat(kH, kW, CV_32F, cv::Scalar(1.5f))), 0);   // occluded then
    EXPECT_EQ(filled(cv::Mat(kH, kW, CV_32F, cv::Scalar(0.f))), 0);    // no old depth
    // A depth edge one pixel off (the old frame's far side starts a column early): the pixels
    // next to the edge have a near old neighbour, so they do not count.
    cv::Mat edge(kH, kW, CV_32F, cv::Scalar(2.f));
    edge.colRange(80, kW).setTo(3.f);
    cv::Mat current(kH, kW, CV_32F, cv::Scalar(2.f));
    current.colRange(81, kW).setTo(3.f);
    EXPECT_EQ(cv::countNonZero(free_space_filled(vertex_of(current), edge, same, 100.f, 100.f,
                                                 80.f, 60.f, c)),
              0);
    // Only the candidates are tested.
    cv::Mat candidates = cv::Mat::zeros(kH, kW, CV_8UC1);
    candidates(cv::Rect(10, 10, 20, 20)).setTo(1);
    EXPECT_EQ(cv::countNonZero(free_space_filled(vertex_of(depth),
                                                 cv::Mat(kH, kW, CV_32F, cv::Scalar(2.5f)), same,
                                                 100.f, 100.f, 80.f, 60.f, c, candidates)),
              400);
}

TEST(MotionSegmentation, AMoverTheMapFollowedIsFoundWhereItFillsAnOldFramesFreeSpace) {
    // The box came 0.3 m nearer than an older frame saw it, but the static map took it in and
    // followed it: its residual is noise, like the wall's.
    const Scene s = make_scene(false, 0.f, 11);
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    const cv::Rect box(60, 40, 40, 30);
    depth(box).setTo(1.5f);
    cv::Mat old_depth = depth.clone();
    old_depth(box).setTo(1.8f);
    cv::Mat truth = cv::Mat::zeros(kH, kW, CV_8UC1);
    truth(box).setTo(255);
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    ASSERT_TRUE(c.free_space_filled) << "on by default";
    MotionInput in = input_of(s);
    in.depth_m = depth;
    auto alone = segment_motion(in, c);
    ASSERT_TRUE(alone.is_ok());
    EXPECT_EQ(alone->mask_pixels, 0) << "its residual alone says nothing";
    // The older frame's free space as SLAM would make it, from the old depth `seen`.
    const auto older_frame = [&](const cv::Mat& seen) {
        return [&, seen](const cv::Mat& candidates) {
            return free_space_filled(vertex_of(depth), seen, Eigen::Isometry3f::Identity(),
                                     100.f, 100.f, 80.f, 60.f, c, candidates);
        };
    };
    in.filled_source = older_frame(old_depth);
    auto found = segment_motion(in, c);
    ASSERT_TRUE(found.is_ok()) << found.status().message();
    EXPECT_GT(found->filled_pixels, 0);
    EXPECT_GT(iou(found->mask, truth), 0.99) << "the whole segment, grown from its filled pixels";
    // The same scene with the older frame seeing it where it is now: nothing.
    in.filled_source = older_frame(depth);
    auto still_box = segment_motion(in, c);
    ASSERT_TRUE(still_box.is_ok());
    EXPECT_EQ(still_box->mask_pixels, 0);
    // Off by the configuration.
    c.free_space_filled = false;
    in.filled_source = older_frame(old_depth);
    auto off = segment_motion(in, c);
    ASSERT_TRUE(off.is_ok());
    EXPECT_EQ(off->mask_pixels, 0);
}

TEST(MotionSegmentation, SomethingTheMapLacksButThatStoodStillIsNotAMover) {
    // The box of the scene stands 0.15 m in front of the wall the static map shows behind it
    // (a chair a flickering detection kept out of the map): dynamic by its residual.
    const Scene s = make_scene(true, 0.15f, 7);
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    depth.setTo(1.85f, s.truth);
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    MotionInput in = input_of(s);
    in.depth_m = depth;
    const Eigen::Isometry3f same = Eigen::Isometry3f::Identity();
    const auto evidence = [&](const cv::Mat& old_depth, const cv::Mat& old_rigid) {
        return history_evidence(vertex_of(depth), s.residual, old_depth, old_rigid, same, 100.f,
                                100.f, 80.f, 60.f, c);
    };
    // The frame 15 frames back saw the box where it is now, as a rigid instance: still, not
    // flagged.
    in.history = evidence(depth, s.truth);
    auto still = segment_motion(in, c);
    ASSERT_TRUE(still.is_ok()) << still.status().message();
    EXPECT_EQ(still->mask_pixels, 0);
    EXPECT_EQ(still->still_segments, 1);
    // It saw the box there but not as an instance (a mover that paused, flagged then): a mover.
    in.history = evidence(depth, cv::Mat::zeros(kH, kW, CV_8UC1));
    auto paused = segment_motion(in, c);
    ASSERT_TRUE(paused.is_ok());
    EXPECT_GT(iou(paused->mask, s.truth), 0.99);
    EXPECT_EQ(paused->still_segments, 0);
    // It saw the box 30 px to the left: the wall showed through most of where it is now.
    cv::Mat old_depth(kH, kW, CV_32F, cv::Scalar(2.f));
    old_depth(cv::Rect(30, 40, 40, 30)).setTo(1.85f);
    cv::Mat old_box = cv::Mat::zeros(kH, kW, CV_8UC1);
    old_box(cv::Rect(30, 40, 40, 30)).setTo(255);
    in.history = evidence(old_depth, old_box);
    auto moved = segment_motion(in, c);
    ASSERT_TRUE(moved.is_ok());
    EXPECT_GT(iou(moved->mask, s.truth), 0.99);
    EXPECT_EQ(moved->still_segments, 0);
    // Without an old frame (the first frames of a run) nothing is vetoed.
    in.history = cv::Mat();
    auto unknown = segment_motion(in, c);
    ASSERT_TRUE(unknown.is_ok());
    EXPECT_GT(iou(unknown->mask, s.truth), 0.99);
    // history_frames 0 turns the veto off.
    in.history = evidence(depth, s.truth);
    c.history_frames = 0;
    auto off = segment_motion(in, c);
    ASSERT_TRUE(off.is_ok());
    EXPECT_GT(iou(off->mask, s.truth), 0.99);
}

TEST(MotionSegmentation, ProjectionsMadeOnDemandCoverOnlyThePixelsThatDecide) {
    // The slowing box: its evidence is between the two fractions, so the previous frame's
    // motion decides it, and only its pixels need warping.
    const Scene s = slowing_box();
    MotionSegmentationConfig c;
    c.dilate_px = 0;
    MotionInput in = input_of(s);
    cv::Mat asked;
    int calls = 0;
    in.carried_source = [&](const cv::Mat& needed) {
        ++calls;
        asked = needed.clone();
        cv::Mat carried = s.truth.clone();
        carried.setTo(0, needed == 0);  // what a projection restricted to `needed` gives
        return carried;
    };
    auto lazy = segment_motion(in, c);
    ASSERT_TRUE(lazy.is_ok()) << lazy.status().message();
    EXPECT_EQ(calls, 1);
    EXPECT_GT(iou(lazy->mask, s.truth), 0.99) << "the carried motion kept the box dynamic";
    EXPECT_GT(iou(asked != 0, s.truth), 0.99) << "only the undecided box was asked for";

    // A box moving fast is decided by its own residuals: nothing is warped.
    Scene fast = make_scene(true, 0.15f, 5);
    MotionInput fast_in = input_of(fast);
    calls = 0;
    fast_in.carried_source = in.carried_source;
    auto decided = segment_motion(fast_in, c);
    ASSERT_TRUE(decided.is_ok());
    EXPECT_EQ(calls, 0);
    EXPECT_GT(iou(decided->mask, fast.truth), 0.99);

    // The history is asked for on the candidates only, and a restricted one decides the same.
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    depth.setTo(1.85f, fast.truth);
    fast_in.depth_m = depth;
    fast_in.history_source = [&](const cv::Mat& needed) {
        asked = needed.clone();
        return history_evidence(vertex_of(depth), fast.residual, depth, fast.truth,
                                Eigen::Isometry3f::Identity(), 100.f, 100.f, 80.f, 60.f, c,
                                needed);
    };
    auto still = segment_motion(fast_in, c);
    ASSERT_TRUE(still.is_ok());
    EXPECT_EQ(still->mask_pixels, 0);
    EXPECT_EQ(still->still_segments, 1);
    EXPECT_GT(iou(asked != 0, fast.truth), 0.99);
}

TEST(MotionSegmentation, RestrictedProjectionsEqualTheFullOnesWhereNeeded) {
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.f));
    const cv::Mat vertex = vertex_of(depth);
    Eigen::Isometry3f moved = Eigen::Isometry3f::Identity();
    moved.translation() = Eigen::Vector3f(0.1f, 0.f, 0.f);
    cv::Mat needed = cv::Mat::zeros(kH, kW, CV_8UC1);
    needed(cv::Rect(20, 10, 70, 50)).setTo(1);
    cv::Mat previous = cv::Mat::zeros(kH, kW, CV_8UC1);
    previous(cv::Rect(40, 20, 60, 60)).setTo(255);
    const cv::Mat old_depth(kH, kW, CV_32F, cv::Scalar(2.5f));
    const MotionSegmentationConfig c;
    const auto same_where_needed = [&](const cv::Mat& full, const cv::Mat& part) {
        EXPECT_EQ(cv::countNonZero(part & (needed == 0)), 0) << "nothing outside `needed`";
        cv::Mat full_inside = full.clone();
        full_inside.setTo(0, needed == 0);
        EXPECT_EQ(cv::countNonZero(full_inside != part), 0);
        EXPECT_GT(cv::countNonZero(part), 0);
    };
    same_where_needed(warp_mask(previous, vertex, moved, 100.f, 100.f, 80.f, 60.f),
                      warp_mask(previous, vertex, moved, 100.f, 100.f, 80.f, 60.f, needed));
    same_where_needed(
        history_evidence(vertex, cv::Mat(), old_depth, cv::Mat(), moved, 100.f, 100.f, 80.f,
                         60.f, c),
        history_evidence(vertex, cv::Mat(), old_depth, cv::Mat(), moved, 100.f, 100.f, 80.f,
                         60.f, c, needed));
}

TEST(MotionSegmentation, BadInputNamesTheImage) {
    Scene s = make_scene(true, 0.15f, 6);
    MotionInput in = input_of(s);
    in.depth_m = cv::Mat(10, 10, CV_32F);
    auto r = segment_motion(in, MotionSegmentationConfig{});
    ASSERT_FALSE(r.is_ok());
    EXPECT_NE(r.status().message().find("depth_m must be CV_32FC1 160x120, got CV_32FC1 10x10"),
              std::string::npos)
        << r.status().message();
    MotionSegmentationConfig bad;
    bad.min_segment_fraction = 2.f;
    r = segment_motion(input_of(s), bad);
    ASSERT_FALSE(r.is_ok());
    EXPECT_NE(r.status().message().find("min_segment_fraction"), std::string::npos);
}

}  // namespace
}  // namespace df::dynamics
