// SurfelMap::predict on ray-cast planes and boxes whose depth, normals and colours are known.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "map/surfel_map.hpp"
#include "synthetic_scene.hpp"

namespace df::map {
namespace {

using testing::Box;
using testing::intrinsics_for;
using testing::Plane;
using testing::render;
using testing::Scene;
using testing::View;

constexpr int kWidth = 128;
constexpr int kHeight = 96;

Eigen::Isometry3f pose(const Eigen::Vector3f& translation, float yaw_rad = 0.f,
                       float pitch_rad = 0.f) {
    Eigen::Isometry3f world_T_camera = Eigen::Isometry3f::Identity();
    world_T_camera.linear() = (Eigen::AngleAxisf(yaw_rad, Eigen::Vector3f::UnitY()) *
                               Eigen::AngleAxisf(pitch_rad, Eigen::Vector3f::UnitX()))
                                  .toRotationMatrix();
    world_T_camera.translation() = translation;
    return world_T_camera;
}

/// A plane through (0, 0, 1.5) turned 30 degrees about y: its depth varies across the image.
Scene tilted_plane() {
    const Eigen::Vector3f normal(std::sin(0.52f), 0.f, -std::cos(0.52f));
    return Scene{{Plane{normal, normal.z() * 1.5f, 60}}, {}};
}

void fuse(SurfelMap& map, const Scene& scene, const Eigen::Isometry3f& world_T_camera, int frame) {
    const View view = render(scene, world_T_camera, kWidth, kHeight);
    const auto stats = map.fuse(view.vertex, view.normal, view.rgb, {}, {}, world_T_camera,
                                intrinsics_for(kWidth, kHeight), frame);
    ASSERT_TRUE(stats.is_ok()) << stats.status().to_string();
}

ModelPrediction predict(const SurfelMap& map, const Eigen::Isometry3f& world_T_camera, int frame,
                        const PredictionConfig& config = {}) {
    auto prediction = map.predict(world_T_camera, intrinsics_for(kWidth, kHeight), kWidth, kHeight,
                                  frame, config);
    EXPECT_TRUE(prediction.is_ok()) << prediction.status().to_string();
    return prediction.is_ok() ? *prediction : ModelPrediction{};
}

/// How a prediction compares with the ray-cast truth over the pixels [margin, size - margin).
struct Agreement {
    size_t truth = 0;      ///< pixels where the truth sees a surface
    size_t covered = 0;    ///< ... and the prediction too
    size_t depth_ok = 0;   ///< ... within 1 mm of the true depth
    size_t normal_ok = 0;  ///< ... with a normal within 0.5 degrees of the truth
    size_t colour_ok = 0;  ///< ... with every colour channel within 6 of the truth
};

Agreement compare(const ModelPrediction& prediction, const View& truth, int margin) {
    Agreement a;
    for (int v = margin; v < kHeight - margin; ++v) {
        for (int u = margin; u < kWidth - margin; ++u) {
            const cv::Vec3f& p_true = truth.vertex.at<cv::Vec3f>(v, u);
            if (p_true[2] <= 0.f) continue;
            ++a.truth;
            if (prediction.index.at<int32_t>(v, u) < 0) continue;
            ++a.covered;
            const cv::Vec3f& p = prediction.vertex.at<cv::Vec3f>(v, u);
            if (std::abs(p[2] - p_true[2]) < 1e-3f) ++a.depth_ok;
            if (prediction.normal.at<cv::Vec3f>(v, u).dot(truth.normal.at<cv::Vec3f>(v, u)) >
                std::cos(0.5f * static_cast<float>(M_PI) / 180.f)) {
                ++a.normal_ok;
            }
            const cv::Vec3b& c = prediction.colour.at<cv::Vec3b>(v, u);
            const cv::Vec3b& c_true = truth.rgb.at<cv::Vec3b>(v, u);
            bool close = true;
            for (int i = 0; i < 3; ++i) close = close && std::abs(c[i] - c_true[i]) <= 6;
            if (close) ++a.colour_ok;
        }
    }
    return a;
}

size_t covered_pixels(const ModelPrediction& prediction) {
    return static_cast<size_t>(cv::countNonZero(prediction.index >= 0));
}

TEST(Prediction, FusedPlaneFromTheFusingPoseHasItsDepthAndNormals) {
    SurfelMap map;
    const Scene scene = tilted_plane();
    const Eigen::Isometry3f world_T_camera = pose({0.1f, -0.05f, 0.f}, 0.1f);
    for (int frame = 0; frame < 3; ++frame) fuse(map, scene, world_T_camera, frame);
    const ModelPrediction prediction = predict(map, world_T_camera, 2);
    ASSERT_EQ(prediction.vertex.type(), CV_32FC3);
    ASSERT_EQ(prediction.normal.type(), CV_32FC3);
    ASSERT_EQ(prediction.colour.type(), CV_8UC3);
    ASSERT_EQ(prediction.index.type(), CV_32SC1);
    ASSERT_EQ(prediction.index.size(), cv::Size(kWidth, kHeight));
    const Agreement a = compare(prediction, render(scene, world_T_camera, kWidth, kHeight), 0);
    ASSERT_EQ(a.truth, static_cast<size_t>(kWidth * kHeight));
    EXPECT_GE(a.covered, a.truth * 99 / 100);
    EXPECT_GE(a.depth_ok, a.truth * 95 / 100);
    EXPECT_EQ(a.normal_ok, a.covered);
}

TEST(Prediction, SplattingFillsTheViewFromNearerPosesWithExactPlaneDepth) {
    SurfelMap map;
    const Scene scene = tilted_plane();
    fuse(map, scene, Eigen::Isometry3f::Identity(), 0);
    // 30 cm nearer, 2 cm aside, turned 2 degrees: the surfels spread over more pixels.
    const Eigen::Isometry3f nearer = pose({0.02f, 0.01f, 0.3f}, 0.035f, -0.02f);
    const View truth = render(scene, nearer, kWidth, kHeight);
    const int margin = kWidth / 10;  // the nearer view's border may leave the fused area
    const Agreement splat = compare(predict(map, nearer, 0), truth, margin);
    ASSERT_GT(splat.truth, 0u);
    EXPECT_EQ(splat.covered, splat.truth);  // no holes
    EXPECT_GE(splat.depth_ok, splat.truth * 95 / 100);
    EXPECT_EQ(splat.normal_ok, splat.covered);
    EXPECT_GE(splat.colour_ok, splat.truth * 95 / 100);

    PredictionConfig points;
    points.splat = false;
    const Agreement holes = compare(predict(map, nearer, 0, points), truth, margin);
    EXPECT_LT(holes.covered, holes.truth * 85 / 100);  // one pixel per surfel leaves holes
}

TEST(Prediction, NearerSurfelWinsAndKeepsItsColour) {
    SurfelMap map;
    const Plane wall{Eigen::Vector3f(0.f, 0.f, 1.f), 2.f, 50};
    const Box box{{-0.2f, -0.15f, 1.f}, {0.2f, 0.15f, 1.3f}, {10, 220, 30}};
    fuse(map, Scene{{wall}, {}}, Eigen::Isometry3f::Identity(), 0);  // the whole wall
    const Scene with_box{{wall}, {box}};
    fuse(map, with_box, Eigen::Isometry3f::Identity(), 1);  // the box, in front of it
    const size_t wall_surfels = kWidth * kHeight;
    ASSERT_GT(map.size(), wall_surfels);

    const Eigen::Isometry3f aside = pose({0.05f, 0.f, 0.f}, -0.02f);
    const View truth = render(with_box, aside, kWidth, kHeight);
    const ModelPrediction prediction = predict(map, aside, 1);
    size_t box_pixels = 0, box_right = 0, wall_right = 0, wall_pixels = 0;
    for (int v = 2; v < kHeight - 2; ++v) {
        for (int u = 2; u < kWidth - 2; ++u) {
            const float z_true = truth.vertex.at<cv::Vec3f>(v, u)[2];
            const int32_t index = prediction.index.at<int32_t>(v, u);
            if (index < 0) continue;
            const float z = prediction.vertex.at<cv::Vec3f>(v, u)[2];
            const Surfel& s = map.surfels()[static_cast<size_t>(index)];
            if (z_true < 1.5f) {
                ++box_pixels;
                if (std::abs(z - z_true) < 1e-3f && s.position.z() < 1.5f &&
                    prediction.colour.at<cv::Vec3b>(v, u) == cv::Vec3b(10, 220, 30)) {
                    ++box_right;
                }
            } else {
                ++wall_pixels;
                if (std::abs(z - z_true) < 1e-3f &&
                    prediction.colour.at<cv::Vec3b>(v, u)[2] == 50) {
                    ++wall_right;
                }
            }
        }
    }
    ASSERT_GT(box_pixels, 500u);
    // The box's silhouette may differ by a pixel where splats overhang its edge.
    EXPECT_GE(box_right, box_pixels * 95 / 100);
    EXPECT_GE(wall_right, wall_pixels * 95 / 100);
}

TEST(Prediction, FiltersLowConfidenceInactiveFarAndBackFacingSurfels) {
    SurfelMap map;
    const Scene scene{{Plane{Eigen::Vector3f(0.f, 0.f, 1.f), 1.5f, 0}}, {}};
    fuse(map, scene, Eigen::Isometry3f::Identity(), 0);  // every confidence <= 1
    const Eigen::Isometry3f camera = Eigen::Isometry3f::Identity();
    const size_t all = covered_pixels(predict(map, camera, 0));
    EXPECT_EQ(all, static_cast<size_t>(kWidth * kHeight));

    PredictionConfig confident;
    confident.min_confidence = 1.5f;
    const ModelPrediction none = predict(map, camera, 0, confident);
    EXPECT_EQ(covered_pixels(none), 0u);
    EXPECT_EQ(cv::countNonZero(none.vertex.reshape(1)), 0);
    EXPECT_EQ(cv::countNonZero(none.normal.reshape(1)), 0);
    EXPECT_EQ(cv::countNonZero(none.colour.reshape(1)), 0);

    const int window = map.config().active_time_window_frames;
    EXPECT_EQ(covered_pixels(predict(map, camera, window)), all);
    EXPECT_EQ(covered_pixels(predict(map, camera, window + 1)), 0u);  // inactive

    PredictionConfig near_only;
    near_only.max_depth_m = 1.4f;
    EXPECT_EQ(covered_pixels(predict(map, camera, 0, near_only)), 0u);
    near_only.max_depth_m = 1.6f;
    EXPECT_EQ(covered_pixels(predict(map, camera, 0, near_only)), all);

    // From behind the plane (at z = 3, looking back along -z) every surfel shows its back.
    const Eigen::Isometry3f behind = pose({0.f, 0.f, 3.f}, static_cast<float>(M_PI));
    EXPECT_EQ(covered_pixels(predict(map, behind, 0)), 0u);
}

TEST(Prediction, IndexImagePointsAtTheSurfelWhoseDiscHoldsTheVertex) {
    SurfelMap map;
    const Scene scene = tilted_plane();
    fuse(map, scene, Eigen::Isometry3f::Identity(), 0);
    fuse(map, scene, pose({0.03f, 0.f, 0.1f}, 0.03f), 1);
    const Eigen::Isometry3f camera = pose({-0.02f, 0.02f, 0.2f}, -0.03f, 0.02f);
    const Eigen::Isometry3f camera_T_world = camera.inverse();
    for (const bool splat : {true, false}) {
        PredictionConfig config;
        config.splat = splat;
        const ModelPrediction prediction = predict(map, camera, 1, config);
        size_t checked = 0;
        for (int v = 0; v < kHeight; ++v) {
            for (int u = 0; u < kWidth; ++u) {
                const int32_t index = prediction.index.at<int32_t>(v, u);
                const cv::Vec3f& p = prediction.vertex.at<cv::Vec3f>(v, u);
                if (index < 0) {
                    EXPECT_EQ(p, cv::Vec3f(0.f, 0.f, 0.f));
                    continue;
                }
                ASSERT_LT(static_cast<size_t>(index), map.size());
                const Surfel& s = map.surfels()[static_cast<size_t>(index)];
                const Eigen::Vector3f centre = camera_T_world * s.position;
                const Eigen::Vector3f vertex(p[0], p[1], p[2]);
                // Splatted: a point of the surfel's disc on this pixel's ray. Points: its centre.
                if (splat) {
                    EXPECT_LT(std::abs((vertex - centre).dot(camera_T_world.linear() * s.normal)),
                              1e-5f);
                    const float ray_sine =
                        vertex.normalized()
                            .cross(Eigen::Vector3f(
                                       static_cast<float>((u - intrinsics_for(kWidth, kHeight).cx) /
                                                          kWidth),
                                       static_cast<float>((v - intrinsics_for(kWidth, kHeight).cy) /
                                                          kWidth),
                                       1.f)
                                       .normalized())
                            .norm();
                    EXPECT_LT(ray_sine, 1e-5f);
                    EXPECT_LE((vertex - centre).norm(), 1.5f * s.radius);
                } else {
                    EXPECT_LT((vertex - centre).norm(), 1e-5f);
                }
                const cv::Vec3f& n = prediction.normal.at<cv::Vec3f>(v, u);
                EXPECT_LT(
                    (Eigen::Vector3f(n[0], n[1], n[2]) - camera_T_world.linear() * s.normal).norm(),
                    1e-5f);
                EXPECT_LT(Eigen::Vector3f(n[0], n[1], n[2]).dot(vertex), 0.f);  // faces us
                const cv::Vec3b& c = prediction.colour.at<cv::Vec3b>(v, u);
                for (int i = 0; i < 3; ++i) EXPECT_EQ(c[i], std::lround(s.colour[i]));
                ++checked;
            }
        }
        EXPECT_GT(checked, static_cast<size_t>(kWidth * kHeight / 2)) << "splat " << splat;
    }
}

TEST(Prediction, OutputDoesNotDependOnTheThreadCount) {
    SurfelMap map;
    const Scene scene{{Plane{Eigen::Vector3f(0.f, 0.f, 1.f), 2.f, 50}},
                      {Box{{-0.3f, -0.2f, 1.f}, {0.1f, 0.25f, 1.4f}, {200, 20, 20}}}};
    for (int frame = 0; frame < 4; ++frame) {
        fuse(map, scene, pose({0.04f * frame, -0.02f * frame, 0.f}, 0.05f * frame), frame);
    }
    const Eigen::Isometry3f camera = pose({0.07f, 0.03f, 0.15f}, 0.08f, 0.04f);
    auto same = [](const cv::Mat& a, const cv::Mat& b) {
        return a.size() == b.size() && a.type() == b.type() &&
               std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
    };
    for (const bool splat : {true, false}) {
        PredictionConfig config;
        config.splat = splat;
        config.threads = 1;
        const ModelPrediction one = predict(map, camera, 3, config);
        EXPECT_GT(covered_pixels(one), static_cast<size_t>(kWidth * kHeight / 2));
        for (const int threads : {2, 3, 7}) {
            config.threads = threads;
            ModelPrediction many;
            many.vertex = cv::Mat(kHeight, kWidth, CV_32FC3, cv::Scalar::all(9));  // reused
            ASSERT_TRUE(map.predict_into(camera, intrinsics_for(kWidth, kHeight), kWidth, kHeight,
                                         3, config, many)
                            .is_ok());
            EXPECT_TRUE(same(one.vertex, many.vertex)) << threads << " threads";
            EXPECT_TRUE(same(one.normal, many.normal)) << threads << " threads";
            EXPECT_TRUE(same(one.colour, many.colour)) << threads << " threads";
            EXPECT_TRUE(same(one.index, many.index)) << threads << " threads";
        }
    }
}

TEST(Prediction, BadInputsAreRejected) {
    SurfelMap map;
    const Eigen::Isometry3f camera = Eigen::Isometry3f::Identity();
    const io::Intrinsics k = intrinsics_for(kWidth, kHeight);
    auto code = [&](const io::Intrinsics& intrinsics, int width, int height,
                    const PredictionConfig& config) {
        return map.predict(camera, intrinsics, width, height, 0, config).status().code();
    };
    EXPECT_EQ(code(k, kWidth, kHeight, {}), StatusCode::kOk);
    EXPECT_EQ(code(k, 0, kHeight, {}), StatusCode::kInvalidArgument);
    EXPECT_EQ(code(k, kWidth, -1, {}), StatusCode::kInvalidArgument);
    EXPECT_EQ(code(k, 40000, kHeight, {}), StatusCode::kInvalidArgument);
    io::Intrinsics bad = k;
    bad.fx = 0.0;
    EXPECT_EQ(code(bad, kWidth, kHeight, {}), StatusCode::kInvalidArgument);
    bad = k;
    bad.fy = -100.0;
    EXPECT_EQ(code(bad, kWidth, kHeight, {}), StatusCode::kInvalidArgument);
    bad = k;
    bad.cx = std::nan("");
    EXPECT_EQ(code(bad, kWidth, kHeight, {}), StatusCode::kInvalidArgument);
    PredictionConfig config;
    config.max_splat_radius_px = 100.f;
    EXPECT_EQ(code(k, kWidth, kHeight, config), StatusCode::kInvalidArgument);
    config = {};
    config.min_cos_incidence = 1.5f;
    EXPECT_EQ(code(k, kWidth, kHeight, config), StatusCode::kInvalidArgument);
    config = {};
    config.max_depth_m = -1.f;
    EXPECT_EQ(code(k, kWidth, kHeight, config), StatusCode::kInvalidArgument);
    const auto status = map.predict(camera, bad, kWidth, kHeight, 0);
    EXPECT_NE(status.status().message().find("cx"), std::string::npos);
}

/// A wall fused for `frames` frames (confident), then a box in front of it fused once (not).
SurfelMap wall_with_new_box(int frames, const Scene& box_scene) {
    SurfelMap map;
    const Scene wall{{box_scene.planes}, {}};
    for (int frame = 0; frame < frames; ++frame) {
        fuse(map, wall, pose({0.01f * frame, 0.f, 0.f}), frame);
    }
    fuse(map, box_scene, pose({0.01f * frames, 0.f, 0.f}), frames);
    return map;
}

Scene wall_and_box() {
    return Scene{{Plane{Eigen::Vector3f(0.f, 0.f, 1.f), 2.f, 50}},
                 {Box{{-0.3f, -0.2f, 1.2f}, {0.1f, 0.25f, 1.5f}, {200, 20, 20}}}};
}

TEST(Prediction, TwoLayersAreTheRenderingsOfAllAndOfConfidentSurfels) {
    const SurfelMap map = wall_with_new_box(6, wall_and_box());
    const Eigen::Isometry3f camera = pose({0.05f, 0.02f, 0.f}, 0.03f);
    PredictionConfig all;
    PredictionConfig confident;
    confident.min_confidence = 2.f;
    const ModelPrediction every = predict(map, camera, 6, all);
    const ModelPrediction wall_only = predict(map, camera, 6, confident);
    TwoLayerPrediction layers;
    ASSERT_TRUE(map.predict_two_layers(camera, intrinsics_for(kWidth, kHeight), kWidth, kHeight, 6,
                                       all, confident.min_confidence, layers)
                    .is_ok());
    // The box hides part of the wall in the first layer, not in the second.
    EXPECT_GT(cv::countNonZero(every.index != wall_only.index), kWidth * kHeight / 10);
    EXPECT_EQ(cv::countNonZero(layers.index != every.index), 0);
    EXPECT_EQ(cv::countNonZero(layers.second_index != wall_only.index), 0);
}

TEST(Prediction, RefreshedAfterFusionIsTheRenderingOfTheFusedMap) {
    // The camera sees the wall again with the box gone: fusion updates the wall's surfels and
    // removes the box's (seen through). The refreshed rendering must show the wall everywhere,
    // as a new rendering of the fused map does.
    const Scene scene = wall_and_box();
    SurfelMap map = wall_with_new_box(6, scene);
    const std::vector<Surfel> before = map.surfels();
    const Eigen::Isometry3f camera = pose({0.06f, 0.f, 0.f});
    const io::Intrinsics k = intrinsics_for(kWidth, kHeight);
    PredictionConfig config;
    config.min_confidence = 2.f;
    TwoLayerPrediction layers;
    PredictionConfig all = config;
    all.min_confidence = 0.f;
    ASSERT_TRUE(map.predict_two_layers(camera, k, kWidth, kHeight, 7, all, config.min_confidence,
                                       layers)
                    .is_ok());
    const View wall = render(Scene{scene.planes, {}}, camera, kWidth, kHeight);
    std::vector<int32_t> index_after;
    FuseOptions options;
    options.index_after = &index_after;
    const auto stats =
        map.fuse(wall.vertex, wall.normal, wall.rgb, {}, layers.index, camera, k, 7, options);
    ASSERT_TRUE(stats.is_ok()) << stats.status().to_string();
    EXPECT_GT(stats->removed_free_space, 100u);

    // index_after: each surviving surfel maps to itself (same birth, same place); the others
    // are exactly the removed ones.
    ASSERT_EQ(index_after.size(), before.size());
    size_t gone = 0;
    for (size_t i = 0; i < before.size(); ++i) {
        if (index_after[i] < 0) {
            ++gone;
            continue;
        }
        const Surfel& now = map.surfels()[static_cast<size_t>(index_after[i])];
        EXPECT_EQ(now.init_frame, before[i].init_frame);
        EXPECT_LT((now.position - before[i].position).norm(), 0.02f);
    }
    EXPECT_EQ(gone, stats->removed + stats->removed_free_space);

    ModelPrediction refreshed;
    ASSERT_TRUE(
        map.refresh_prediction(index_after, layers, camera, k, config.min_confidence, config,
                               refreshed)
            .is_ok());
    const ModelPrediction rendered = predict(map, camera, 7, config);
    const int pixels = kWidth * kHeight;
    EXPECT_GE(cv::countNonZero(refreshed.index == rendered.index), pixels * 98 / 100);
    const Agreement a = compare(refreshed, wall, 2);
    EXPECT_GE(a.covered, a.truth * 98 / 100);
    EXPECT_GE(a.depth_ok, a.truth * 95 / 100);
    EXPECT_GE(a.colour_ok, a.truth * 95 / 100);

    // Index images of another size are rejected.
    TwoLayerPrediction wrong = layers;
    wrong.second_index = cv::Mat(3, 3, CV_32SC1, cv::Scalar(-1));
    EXPECT_EQ(map.refresh_prediction(index_after, wrong, camera, k, 2.f, config, refreshed).code(),
              StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace df::map
