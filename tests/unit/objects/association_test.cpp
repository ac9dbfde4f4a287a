// Association of rendered object maps with a frame's instances: which instance feeds which map,
// which pixels each map claims, and what stays with persons and unknown movers.
#include "objects/association.hpp"

#include <gtest/gtest.h>

namespace df::objects {
namespace {

constexpr int kW = 64, kH = 48;

/// A frame: depth 2 m everywhere; the instances given as (id, class, kind, rect).
struct Scene {
    cv::Mat depth = cv::Mat(kH, kW, CV_32F, cv::Scalar(2.f));
    dynamics::LabelImage instances{cv::Mat::zeros(kH, kW, CV_16UC1), {}};

    void add(uint16_t id, int class_id, dynamics::ObjectKind kind, const cv::Rect& r) {
        instances.labels(r).setTo(id);
        dynamics::InstanceInfo row;
        row.id = id;
        row.class_id = class_id;
        row.kind = kind;
        row.box = cv::Rect2f(r);
        row.pixels = r.area();
        instances.instances.push_back(row);
    }
};

/// A map rendered over `r` at depth z.
ObjectView view(int class_id, const cv::Rect& r, float z = 2.f) {
    ObjectView v;
    v.class_id = class_id;
    v.depth_m = cv::Mat::zeros(kH, kW, CV_32F);
    v.depth_m(r).setTo(z);
    return v;
}

int count(const cv::Mat& labels, int value) { return cv::countNonZero(labels == value); }

TEST(Association, AnInstanceFeedsTheMapWhoseRenderingCoversItWithItsClass) {
    Scene s;
    s.add(1, 2, dynamics::ObjectKind::kRigid, {10, 10, 10, 10});   // a car
    s.add(2, 28, dynamics::ObjectKind::kRigid, {40, 10, 10, 10});  // a suitcase
    // The car's map moved 3 px since (70 % overlap); the suitcase's map is elsewhere.
    const Association a =
        associate(s.instances, {view(2, {13, 10, 10, 10}), view(28, {40, 30, 8, 8})}, s.depth,
                  AssociationConfig{});
    EXPECT_EQ(a.instance_of_view[0], 1);
    EXPECT_EQ(a.instance_of_view[1], 0);
    ASSERT_EQ(a.unmatched_rigid.size(), 1u);
    EXPECT_EQ(a.unmatched_rigid[0], 2);
    // The car's map claims the instance's 100 pixels, not the 30 of its rendering beside it
    // (silhouettes count only for maps the detector missed).
    EXPECT_EQ(a.pixels_of_view[0], 100);
    EXPECT_EQ(count(a.view_labels, 1), 100);
    EXPECT_EQ(count(a.view_labels(cv::Rect(10, 10, 10, 10)), 1), 100);
    // The suitcase map, missed by the detector, claims its rendered pixels whose depth agrees.
    EXPECT_EQ(a.pixels_of_view[1], 64);
    EXPECT_EQ(a.silhouette_pixels_of_view[1], 64);
}

TEST(Association, ClassesMustAgreeUnlessConfiguredOtherwise) {
    Scene s;
    s.add(1, 7, dynamics::ObjectKind::kRigid, {10, 10, 10, 10});  // a truck, where a car was
    AssociationConfig config;
    config.any_class_overlap = 1.f;
    Association a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth, config);
    EXPECT_EQ(a.instance_of_view[0], 0);
    // Mostly inside the car map's silhouette: claimed by it, and said so (no new object).
    ASSERT_EQ(a.unmatched_claimed.size(), 1u);
    EXPECT_EQ(a.unmatched_claimed[0], 100);
    config.class_must_agree = false;
    a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth, config);
    EXPECT_EQ(a.instance_of_view[0], 1);
    // The same surface named otherwise (all of it inside the car map's silhouette) feeds it.
    config.class_must_agree = true;
    config.any_class_overlap = 0.6f;
    a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth, config);
    EXPECT_EQ(a.instance_of_view[0], 1);
    a = associate(s.instances, {view(2, {15, 10, 10, 10})}, s.depth, config);  // half of it
    EXPECT_EQ(a.instance_of_view[0], 0);
}

TEST(Association, TooLittleOverlapIsNoMatch) {
    Scene s;
    s.add(1, 2, dynamics::ObjectKind::kRigid, {10, 10, 10, 10});
    const Association a =
        associate(s.instances, {view(2, {18, 10, 10, 10})}, s.depth, AssociationConfig{});
    EXPECT_EQ(a.instance_of_view[0], 0);  // 20 % < 30 %
    EXPECT_EQ(a.unmatched_rigid.size(), 1u);
}

TEST(Association, EachInstanceFeedsOneMapAndEachMapTakesOneInstance) {
    Scene s;
    s.add(1, 2, dynamics::ObjectKind::kRigid, {10, 10, 10, 10});
    s.add(2, 2, dynamics::ObjectKind::kRigid, {30, 10, 10, 10});
    // Map 0 covers all of instance 1 and half of instance 2; map 1 covers instance 2 whole.
    const Association a =
        associate(s.instances, {view(2, {10, 10, 25, 10}), view(2, {30, 10, 10, 10}, 1.5f)},
                  s.depth, AssociationConfig{});
    EXPECT_EQ(a.instance_of_view[0], 1);
    EXPECT_EQ(a.instance_of_view[1], 2);
    EXPECT_TRUE(a.unmatched_rigid.empty());
}

TEST(Association, PersonsAndUnknownMoversKeepTheirPixels) {
    Scene s;
    s.add(1, 0, dynamics::ObjectKind::kNonRigid, {10, 10, 5, 10});  // a person before the car
    s.add(2, -1, dynamics::ObjectKind::kUnknown, {15, 10, 5, 10});
    const Association a =
        associate(s.instances, {view(2, {10, 10, 20, 10})}, s.depth, AssociationConfig{});
    EXPECT_EQ(a.instance_of_view[0], 0);  // never matched to a person or a mover
    EXPECT_EQ(count(a.view_labels(cv::Rect(10, 10, 10, 10)), 1), 0);
    EXPECT_EQ(a.pixels_of_view[0], 100);  // the 10 x 10 silhouette pixels left
}

TEST(Association, ASilhouettePixelNeedsTheFramesDepthThere) {
    Scene s;
    s.depth(cv::Rect(10, 10, 5, 10)).setTo(2.5f);  // the object left this part: floor behind
    s.depth(cv::Rect(15, 10, 2, 10)).setTo(0.f);   // no depth
    AssociationConfig config;
    config.min_silhouette_fraction = 0.f;
    Association a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth, config);
    EXPECT_EQ(a.pixels_of_view[0], 30);
    EXPECT_EQ(count(a.view_labels(cv::Rect(17, 10, 3, 10)), 1), 30);
    // 30 of the 80 rendered pixels with a depth agree: too little of it to say it is there.
    config.min_silhouette_fraction = 0.5f;
    a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth, config);
    EXPECT_EQ(a.pixels_of_view[0], 0);
    EXPECT_EQ(count(a.view_labels, 1), 0);
}

TEST(Association, WhatTheBackgroundExplainsStaysTheBackgrounds) {
    Scene s;  // a map rendered at 2 m over a frame at 2 m, where the static map is 2.01 m too
    cv::Mat background(kH, kW, CV_32F, cv::Scalar(2.01f));
    background(cv::Rect(10, 10, 5, 10)).setTo(3.f);  // here the static map is far behind
    const Association a = associate(s.instances, {view(2, {10, 10, 10, 10})}, s.depth,
                                    AssociationConfig{}, background);
    EXPECT_EQ(a.pixels_of_view[0], 50);  // 50 of 100 agree only with the object: kept
    EXPECT_EQ(count(a.view_labels(cv::Rect(10, 10, 5, 10)), 1), 50);
}

TEST(Association, TheNearerOfTwoRenderedMapsOwnsAPixel) {
    Scene s;
    s.depth.setTo(1.f);
    const Association a =
        associate(s.instances, {view(2, {10, 10, 20, 10}, 3.f), view(28, {20, 10, 20, 10}, 1.f)},
                  s.depth, AssociationConfig{});
    // Where both render, map 1 (1 m, as the frame) owns it; map 0's own pixels there are 2 m off.
    EXPECT_EQ(a.pixels_of_view[1], 200);
    EXPECT_EQ(a.pixels_of_view[0], 0);
}

TEST(Association, OneBoxOverTwoMapsIsSplitByTheirSilhouettes) {
    Scene s;
    // One "chair" instance over a suitcase (left) and a car (right) standing side by side.
    s.add(1, 56, dynamics::ObjectKind::kRigid, {10, 10, 30, 10});
    const std::vector<ObjectView> views = {view(56, {10, 10, 15, 10}),  // the suitcase's map
                                           view(2, {25, 10, 15, 10})};  // the car's map
    const Association a = associate(s.instances, views, s.depth, AssociationConfig{});
    EXPECT_EQ(a.instance_of_view[0], 1);  // the instance matches one of them ...
    EXPECT_EQ(a.instance_of_view[1], 0);
    // ... and each map gets its own half: the car's pixels are not fused into the suitcase.
    EXPECT_EQ(a.pixels_of_view[0], 150);
    EXPECT_EQ(a.pixels_of_view[1], 150);
    EXPECT_EQ(count(a.view_labels(cv::Rect(25, 10, 15, 10)), 2), 150);
    EXPECT_EQ(count(a.view_labels(cv::Rect(10, 10, 15, 10)), 1), 150);
    // Where the frame's depth disagrees with the car's rendering (the car left), the pixels
    // stay the matched instance's; too little of the car agrees, so it claims nothing.
    s.depth(cv::Rect(25, 10, 15, 10)).setTo(2.5f);
    const Association moved = associate(s.instances, views, s.depth, AssociationConfig{});
    EXPECT_EQ(moved.pixels_of_view[0], 300);
    EXPECT_EQ(moved.pixels_of_view[1], 0);
    // Switched off: the matched instance's pixels all feed its map.
    s.depth.setTo(2.f);
    AssociationConfig whole;
    whole.split_instances_by_silhouette = false;
    const Association one = associate(s.instances, views, s.depth, whole);
    EXPECT_EQ(one.pixels_of_view[0], 300);
    EXPECT_EQ(one.pixels_of_view[1], 0);
}

TEST(Association, MotionRegionsOutsideInstancesAndClaimsBecomeUnmatchedRigidInstancesOfNoClass) {
    Scene s;
    s.add(1, 56, dynamics::ObjectKind::kRigid, cv::Rect(0, 0, 10, 10));  // a chair
    cv::Mat motion = cv::Mat::zeros(kH, kW, CV_8UC1);
    motion(cv::Rect(30, 10, 20, 20)).setTo(255);  // a mover, 400 px, free
    motion(cv::Rect(0, 0, 12, 12)).setTo(255);    // mostly the chair: 100 of 144 px
    motion(cv::Rect(60, 40, 3, 3)).setTo(255);    // too small
    cv::Mat claims = cv::Mat::zeros(kH, kW, CV_16UC1);
    claims(cv::Rect(30, 10, 5, 20)).setTo(7);  // a map claims 100 px of the mover's region
    Association a;
    const int added = add_motion_regions(motion, claims, 50, &s.instances, &a);
    ASSERT_EQ(added, 1);
    ASSERT_EQ(s.instances.instances.size(), 2u);
    const dynamics::InstanceInfo& row = s.instances.instances.back();
    EXPECT_EQ(row.id, 2);
    EXPECT_EQ(row.class_id, -1);
    EXPECT_EQ(row.kind, dynamics::ObjectKind::kRigid);
    EXPECT_EQ(row.pixels, 300);  // the region less the map's claim
    EXPECT_EQ(count(s.instances.labels, 2), 300);
    EXPECT_EQ(count(s.instances.labels, 1), 100);  // the chair keeps its pixels
    EXPECT_FLOAT_EQ(row.box.x, 35.f);
    EXPECT_FLOAT_EQ(row.box.width, 15.f);
    ASSERT_EQ(a.unmatched_rigid.size(), 1u);
    EXPECT_EQ(a.unmatched_rigid[0], 2);
    EXPECT_EQ(a.unmatched_claimed[0], 0);
    // Labels are made when the frame has none; no motion adds nothing.
    dynamics::LabelImage none;
    Association b;
    EXPECT_EQ(add_motion_regions(motion, cv::Mat(), 50, &none, &b), 2);
    EXPECT_EQ(none.labels.size(), motion.size());
    EXPECT_EQ(add_motion_regions(cv::Mat::zeros(kH, kW, CV_8UC1), cv::Mat(), 50, &none, &b), 0);
}

TEST(Association, BoxIou) {
    EXPECT_FLOAT_EQ(box_iou({0, 0, 10, 10}, {0, 0, 10, 10}), 1.f);
    EXPECT_FLOAT_EQ(box_iou({0, 0, 10, 10}, {5, 0, 10, 10}), 50.f / 150.f);
    EXPECT_FLOAT_EQ(box_iou({0, 0, 10, 10}, {20, 0, 10, 10}), 0.f);
    EXPECT_FLOAT_EQ(box_iou({}, {0, 0, 10, 10}), 0.f);
}

}  // namespace
}  // namespace df::objects
