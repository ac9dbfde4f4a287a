// SurfelMap on synthetic fronto-parallel planes whose answer is known.
#include "map/surfel_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "io/ply/ply.hpp"

namespace df::map {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr size_t kPixels = static_cast<size_t>(kWidth) * kHeight;

io::Intrinsics intrinsics_for(int width, int height) {
    const double f = width;  // ~53 degrees horizontal field of view
    return {f, f, 0.5 * (width - 1), 0.5 * (height - 1)};
}

/// Vertex, normal and colour maps of the plane z = depth_m (camera frame), seen head-on.
/// `depth_noise_m` moves each vertex along its ray, so it stays on its pixel.
struct View {
    cv::Mat vertex, normal, rgb;
};

View plane_view(float depth_m, int width = kWidth, int height = kHeight, float depth_noise_m = 0.f,
                std::mt19937* rng = nullptr,
                Eigen::Vector3f normal_cam = Eigen::Vector3f(0.f, 0.f, -1.f)) {
    const io::Intrinsics k = intrinsics_for(width, height);
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    View view{cv::Mat(height, width, CV_32FC3), cv::Mat(height, width, CV_32FC3),
              cv::Mat(height, width, CV_8UC3)};
    std::normal_distribution<float> noise(0.f, depth_noise_m);
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const float z = depth_m + (rng != nullptr ? noise(*rng) : 0.f);
            view.vertex.at<cv::Vec3f>(v, u) = {(u - cx) / fx * z, (v - cy) / fy * z, z};
            view.normal.at<cv::Vec3f>(v, u) = {normal_cam.x(), normal_cam.y(), normal_cam.z()};
            view.rgb.at<cv::Vec3b>(v, u) = {static_cast<uint8_t>(u * 3), 100,
                                            static_cast<uint8_t>(v * 5)};
        }
    }
    return view;
}

Result<FusionStats> fuse(SurfelMap& map, const View& view, int frame, const cv::Mat& mask = {},
                         const cv::Mat& index_map = {},
                         const Eigen::Isometry3f& world_T_camera = Eigen::Isometry3f::Identity()) {
    return map.fuse(view.vertex, view.normal, view.rgb, mask, index_map, world_T_camera,
                    intrinsics_for(view.vertex.cols, view.vertex.rows), frame);
}

/// How many pixels reach `confidence` after `frames` observations of weight exp(-r^2/0.72).
size_t pixels_reaching(float confidence, int frames) {
    const io::Intrinsics k = intrinsics_for(kWidth, kHeight);
    const float half_diagonal = 0.5f * std::sqrt(float(kWidth * kWidth + kHeight * kHeight));
    size_t count = 0;
    for (int v = 0; v < kHeight; ++v) {
        for (int u = 0; u < kWidth; ++u) {
            const float r = static_cast<float>(std::hypot(u - k.cx, v - k.cy)) / half_diagonal;
            if (frames * std::exp(-r * r / 0.72f) >= confidence) ++count;
        }
    }
    return count;
}

TEST(SurfelMap, SameViewMergesInsteadOfDuplicatingAndBecomesStable) {
    SurfelMap map;
    const View view = plane_view(1.5f);
    const int frames = 15;
    for (int frame = 0; frame < frames; ++frame) {
        const auto stats = fuse(map, view, frame);
        ASSERT_TRUE(stats.is_ok()) << stats.status().to_string();
        EXPECT_EQ(stats->total, kPixels) << "frame " << frame;
        EXPECT_EQ(stats->created, frame == 0 ? kPixels : 0u);
        EXPECT_EQ(stats->fused, frame == 0 ? 0u : kPixels);
        if (frame == 0) {
            EXPECT_EQ(stats->stable, 0u);
        }
    }
    // Confidence is the sum of the weights: centre pixels (weight ~1) pass 10 after 10 frames,
    // the corners (weight exp(-1/0.72) = 0.25) need 40.
    const size_t stable = map.stable_count();
    EXPECT_GE(stable, pixels_reaching(10.01f, frames));
    EXPECT_LE(stable, pixels_reaching(9.99f, frames));
    EXPECT_GT(stable, kPixels / 3);
    EXPECT_LT(stable, kPixels);
    for (const Surfel& s : map.surfels()) {
        EXPECT_NEAR(s.position.z(), 1.5f, 1e-5f);
        EXPECT_NEAR(s.normal.z(), -1.f, 1e-5f);
        EXPECT_NEAR(s.radius, 1.5f / kWidth * std::sqrt(2.f), 1e-6f);
        EXPECT_EQ(s.last_seen_frame, frames - 1);
    }
}

TEST(SurfelMap, NoisyObservationsAverageTowardsThePlane) {
    const float sigma = 0.005f;
    std::mt19937 rng(7);
    SurfelMap map;
    auto rms_error = [&map] {
        double sum = 0.0;
        for (const Surfel& s : map.surfels()) sum += std::pow(s.position.z() - 1.5, 2);
        return std::sqrt(sum / static_cast<double>(map.size()));
    };
    ASSERT_TRUE(fuse(map, plane_view(1.5f, kWidth, kHeight, sigma, &rng), 0).is_ok());
    const double first_error = rms_error();
    for (int frame = 1; frame < 10; ++frame) {
        ASSERT_TRUE(fuse(map, plane_view(1.5f, kWidth, kHeight, sigma, &rng), frame).is_ok());
    }
    EXPECT_EQ(map.size(), kPixels);  // merged, not duplicated
    EXPECT_GT(first_error, 0.8 * sigma);
    // Ten equal-weight samples: sigma / sqrt(10) = 0.32 sigma.
    EXPECT_LT(rms_error(), 0.5 * sigma);
}

TEST(SurfelMap, MaskedPixelsCreateNoSurfels) {
    SurfelMap map;
    cv::Mat mask(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    mask.colRange(0, kWidth / 2).setTo(255);
    const auto stats = fuse(map, plane_view(1.5f), 0, mask);
    ASSERT_TRUE(stats.is_ok());
    EXPECT_EQ(stats->created, kPixels / 2);
    for (const Surfel& s : map.surfels()) EXPECT_GT(s.position.x(), 0.f);
}

TEST(SurfelMap, InvalidPixelsAreSkipped) {
    SurfelMap map;
    View view = plane_view(1.5f);
    view.vertex.row(0).setTo(cv::Scalar(0, 0, 0));             // z = 0
    view.vertex.row(1).setTo(cv::Scalar::all(std::nanf("")));  // NaN
    view.normal.row(2).setTo(cv::Scalar(0, 0, 0));             // no normal
    const auto stats = fuse(map, view, 0);
    ASSERT_TRUE(stats.is_ok());
    EXPECT_EQ(stats->created, kPixels - 3 * kWidth);
}

TEST(SurfelMap, ObservationOffTheSurfaceCreatesNewSurfels) {
    SurfelMap map;
    ASSERT_TRUE(fuse(map, plane_view(1.5f), 0).is_ok());
    const auto near = fuse(map, plane_view(1.46f), 1);  // 4 cm: within the 5 cm gate
    ASSERT_TRUE(near.is_ok());
    EXPECT_EQ(near->fused, kPixels);
    const auto off = fuse(map, plane_view(1.4f), 2);  // 10 cm in front
    ASSERT_TRUE(off.is_ok());
    EXPECT_EQ(off->fused, 0u);
    EXPECT_EQ(off->created, kPixels);
    EXPECT_EQ(off->total, 2 * kPixels);
}

TEST(SurfelMap, WithoutCreationAFrameOnlyConfirmsTheSurfelsThere) {
    SurfelMap map;
    cv::Mat left_half(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    left_half.colRange(kWidth / 2, kWidth).setTo(255);
    ASSERT_TRUE(fuse(map, plane_view(1.5f), 0, left_half).is_ok());
    ASSERT_EQ(map.size(), kPixels / 2);
    const float before = map.surfels().front().confidence;
    // The whole plane, and a second layer 10 cm in front: neither may add a surfel.
    const View view = plane_view(1.5f);
    const auto stats = map.fuse(view.vertex, view.normal, view.rgb, cv::Mat(), cv::Mat(),
                                Eigen::Isometry3f::Identity(), intrinsics_for(kWidth, kHeight), 1,
                                FuseOptions{false, {}});
    ASSERT_TRUE(stats.is_ok()) << stats.status().to_string();
    EXPECT_EQ(stats->created, 0u);
    EXPECT_EQ(stats->fused, kPixels / 2);
    // The column next to the mapped half finds its neighbours' surfels in the association
    // window (each already updated by its own pixel: covered); the rest have none.
    EXPECT_EQ(stats->covered, static_cast<size_t>(kHeight));
    EXPECT_EQ(stats->not_created, kPixels / 2 - kHeight);
    EXPECT_EQ(map.size(), kPixels / 2);
    for (const Surfel& s : map.surfels()) EXPECT_LT(s.position.x(), 0.f);
    EXPECT_GT(map.surfels().front().confidence, before);
    const View front = plane_view(1.4f);
    const auto off = map.fuse(front.vertex, front.normal, front.rgb, cv::Mat(), cv::Mat(),
                              Eigen::Isometry3f::Identity(), intrinsics_for(kWidth, kHeight), 2,
                              FuseOptions{false, {}});
    ASSERT_TRUE(off.is_ok());
    EXPECT_EQ(off->created, 0u);
    EXPECT_EQ(map.size(), kPixels / 2);
}

TEST(SurfelMap, NormalAngleGate) {
    const auto tilted = [](float angle) {
        return Eigen::Vector3f(std::sin(angle), 0.f, -std::cos(angle));
    };
    SurfelMap map;
    ASSERT_TRUE(fuse(map, plane_view(1.5f), 0).is_ok());
    const auto small = fuse(map, plane_view(1.5f, kWidth, kHeight, 0.f, nullptr, tilted(0.4f)), 1);
    ASSERT_TRUE(small.is_ok());
    EXPECT_EQ(small->fused, kPixels);
    SurfelMap other;
    ASSERT_TRUE(fuse(other, plane_view(1.5f), 0).is_ok());
    const auto large =
        fuse(other, plane_view(1.5f, kWidth, kHeight, 0.f, nullptr, tilted(0.6f)), 1);
    ASSERT_TRUE(large.is_ok());
    // Known surface with a disagreeing normal: neither fused nor duplicated.
    EXPECT_EQ(large->fused, 0u);
    EXPECT_EQ(large->created, 0u);
    EXPECT_EQ(large->known_surface, kPixels);
    EXPECT_EQ(large->total, kPixels);
}

TEST(SurfelMap, UnstableSurfelsSeenOnceAreRemovedAfter20Frames) {
    SurfelMap map;
    ASSERT_TRUE(fuse(map, plane_view(1.5f), 0).is_ok());
    const View nothing = plane_view(0.f);  // z = 0 everywhere: no valid pixel
    for (int frame = 1; frame <= 20; ++frame) {
        const auto stats = fuse(map, nothing, frame);
        ASSERT_TRUE(stats.is_ok());
        EXPECT_EQ(stats->total, kPixels) << "frame " << frame;
    }
    const auto stats = fuse(map, nothing, 21);
    ASSERT_TRUE(stats.is_ok());
    EXPECT_EQ(stats->removed, kPixels);
    EXPECT_EQ(stats->total, 0u);
}

TEST(SurfelMap, UnstableSurfelsStayWhileTheyAreSeen) {
    // ElasticFusion removes an unstable surfel when it has not been fused for 20 frames, not
    // when it is 20 frames old: surfels at the image rim gain confidence slowly and must not
    // be torn out while the camera still sees them.
    SurfelMapConfig config;
    config.stable_confidence = 1e6f;  // nothing becomes stable
    SurfelMap map(config);
    const View view = plane_view(1.5f);
    for (int frame = 0; frame < 40; ++frame) {
        const auto stats = fuse(map, view, frame);
        ASSERT_TRUE(stats.is_ok());
        EXPECT_EQ(stats->removed, 0u) << "frame " << frame;
    }
    EXPECT_EQ(map.size(), kPixels);
    EXPECT_EQ(map.clean(39 + 20), 0u);
    EXPECT_EQ(map.clean(39 + 21), kPixels);
}

TEST(SurfelMap, StableSurfelsSurviveAndGoInactiveAfter200Frames) {
    SurfelMap map;
    const View view = plane_view(1.5f);
    for (int frame = 0; frame < 15; ++frame) ASSERT_TRUE(fuse(map, view, frame).is_ok());
    ASSERT_TRUE(map.clean(100) > 0);  // the unstable rim goes
    const size_t stable = map.size();
    EXPECT_EQ(map.stable_count(), stable);
    EXPECT_EQ(map.active(14 + 200).size(), stable);
    EXPECT_EQ(map.active(14 + 201).size(), 0u);
    // Inactive surfels are not associated: the same view creates new ones.
    const auto stats = fuse(map, view, 14 + 201);
    ASSERT_TRUE(stats.is_ok());
    EXPECT_EQ(stats->fused, 0u);
    EXPECT_EQ(stats->created, kPixels);
    EXPECT_EQ(stats->total, stable + kPixels);
}

TEST(SurfelMap, CapacityLimitIsNeverExceededAndCounted) {
    SurfelMapConfig config;
    config.max_surfels = 1000;
    SurfelMap map(config);
    const View view = plane_view(1.5f);
    const auto first = fuse(map, view, 0);
    ASSERT_TRUE(first.is_ok());
    EXPECT_EQ(first->total, 1000u);
    EXPECT_EQ(first->created, 1000u);
    EXPECT_EQ(first->rejected_by_capacity, kPixels - 1000);
    EXPECT_TRUE(map.capacity_reached());
    const auto second = fuse(map, view, 1);
    ASSERT_TRUE(second.is_ok());
    EXPECT_EQ(second->total, 1000u);
    EXPECT_EQ(second->fused, 1000u);
    // Pixels next to the 1000 surfels find them in their association window (covered); the
    // others would be new surfels and are rejected.
    EXPECT_GT(second->rejected_by_capacity, 0u);
    EXPECT_EQ(second->fused + second->covered + second->rejected_by_capacity, kPixels);
    EXPECT_EQ(map.total_rejected_by_capacity(),
              first->rejected_by_capacity + second->rejected_by_capacity);
}

TEST(SurfelMap, IndexMapDecidesAssociation) {
    SurfelMap map;
    const View view = plane_view(1.5f);
    ASSERT_TRUE(fuse(map, view, 0).is_ok());
    // Surfels were created in row-major pixel order: surfel i sits at pixel i.
    cv::Mat index_map(kHeight, kWidth, CV_32SC1);
    for (int i = 0; i < static_cast<int>(kPixels); ++i) index_map.at<int32_t>(i) = i;
    const auto merged = fuse(map, view, 1, {}, index_map);
    ASSERT_TRUE(merged.is_ok());
    EXPECT_EQ(merged->fused, kPixels);
    const cv::Mat none(kHeight, kWidth, CV_32SC1, cv::Scalar(-1));
    const auto created = fuse(map, view, 2, {}, none);
    ASSERT_TRUE(created.is_ok());
    EXPECT_EQ(created->created, kPixels);
}

TEST(SurfelMap, PoseMapsObservationsToTheWorld) {
    Eigen::Isometry3f world_T_camera = Eigen::Isometry3f::Identity();
    world_T_camera.linear() =
        Eigen::AngleAxisf(0.3f, Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
    world_T_camera.translation() = Eigen::Vector3f(0.5f, -1.f, 2.f);
    SurfelMap map;
    const View view = plane_view(1.5f);
    ASSERT_TRUE(fuse(map, view, 0, {}, {}, world_T_camera).is_ok());
    ASSERT_EQ(map.size(), kPixels);
    const cv::Vec3f centre = view.vertex.at<cv::Vec3f>(kHeight / 2, kWidth / 2);
    const Surfel& s = map.surfels()[kPixels / 2 + kWidth / 2];
    EXPECT_LT(
        (s.position - world_T_camera * Eigen::Vector3f(centre[0], centre[1], centre[2])).norm(),
        1e-5f);
    EXPECT_LT((s.normal - world_T_camera.linear() * Eigen::Vector3f(0, 0, -1)).norm(), 1e-5f);
    const auto again = fuse(map, view, 1, {}, {}, world_T_camera);
    ASSERT_TRUE(again.is_ok());
    EXPECT_EQ(again->fused, kPixels);
}

TEST(SurfelMap, BadInputsAreRejectedAndLeaveTheMapAlone) {
    SurfelMap map;
    View view = plane_view(1.5f);
    view.rgb = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    const auto stats = fuse(map, view, 0);
    ASSERT_FALSE(stats.is_ok());
    EXPECT_EQ(stats.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(stats.status().message().find("rgb"), std::string::npos);
    EXPECT_EQ(map.size(), 0u);
}

TEST(SurfelMap, PlyRoundTrip) {
    SurfelMap map;
    const View view = plane_view(1.5f);
    for (int frame = 0; frame < 15; ++frame) ASSERT_TRUE(fuse(map, view, frame).is_ok());
    const std::string file =
        (std::filesystem::temp_directory_path() / "df_surfel_map_test.ply").string();
    ASSERT_TRUE(map.write_ply(file, /*stable_only=*/true).is_ok());
    io::PlyReadInfo info;
    auto cloud = io::read_ply(file, &info);
    ASSERT_TRUE(cloud.is_ok()) << cloud.status().to_string();
    EXPECT_EQ(info.format, io::PlyFormat::kBinaryLittleEndian);
    ASSERT_EQ(cloud->size(), map.stable_count());
    ASSERT_TRUE(cloud->has_normals() && cloud->has_colours());
    const auto* radius = cloud->scalar("radius");
    const auto* confidence = cloud->scalar("confidence");
    ASSERT_TRUE(radius != nullptr && confidence != nullptr);
    size_t i = 0;
    for (const Surfel& s : map.surfels()) {
        if (!map.is_stable(s)) continue;
        EXPECT_LT((cloud->positions[i] - s.position.cast<double>()).norm(), 1e-6);
        EXPECT_LT((cloud->normals[i] - s.normal).norm(), 1e-6f);
        EXPECT_EQ(cloud->colours[i].cast<float>(), s.colour.array().round().matrix());
        EXPECT_EQ((*radius)[i], s.radius);
        EXPECT_EQ((*confidence)[i], s.confidence);
        ++i;
    }
    ASSERT_TRUE(map.write_ply(file, /*stable_only=*/false).is_ok());
    auto all = io::read_ply(file);
    ASSERT_TRUE(all.is_ok());
    EXPECT_EQ(all->size(), map.size());
    std::remove(file.c_str());
}

// Not an assertion: prints the time of fuse() on a full VGA frame for the docs.
TEST(SurfelMap, FullResolutionViewsMergeInsteadOfDuplicating) {
    // At 640x480 (the real size) the projection-based association still finds every surfel:
    // the map holds one surfel per pixel however often the same view is fused.
    SurfelMap map;
    const View view = plane_view(1.5f, 640, 480);
    for (int frame = 0; frame < 4; ++frame) {
        const auto stats = fuse(map, view, frame);
        ASSERT_TRUE(stats.is_ok());
        EXPECT_EQ(stats->total, 640u * 480u) << "frame " << frame;
        if (frame > 0) {
            EXPECT_EQ(stats->fused, 640u * 480u) << "frame " << frame;
        }
    }
}

}  // namespace
}  // namespace df::map
