// Free-space violations in SurfelMap::fuse: a box fused in front of a wall, then taken away.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

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
constexpr int kBoxFrames = 20;  // enough for every surfel of the box to be stable

const Plane kWall{Eigen::Vector3f(0.f, 0.f, 1.f), 2.f, 50};
// Front face at 1.2 m, about 54 x 40 pixels in the middle of the image.
const Box kBox{{-0.25f, -0.19f, 1.2f}, {0.25f, 0.19f, 1.6f}, {200, 30, 30}};

Result<FusionStats> fuse(SurfelMap& map, const View& view, int frame, const cv::Mat& mask = {},
                         const Eigen::Isometry3f& world_T_camera = Eigen::Isometry3f::Identity()) {
    return map.fuse(view.vertex, view.normal, view.rgb, mask, {}, world_T_camera,
                    intrinsics_for(kWidth, kHeight), frame);
}

size_t box_surfels(const SurfelMap& map) {
    return static_cast<size_t>(
        std::count_if(map.surfels().begin(), map.surfels().end(),
                      [](const Surfel& s) { return s.position.z() < 1.8f; }));
}

size_t wall_surfels(const SurfelMap& map) { return map.size() - box_surfels(map); }

/// Fuses kBoxFrames frames of the box in front of the wall, then `frames` of the bare wall
/// (masked by `mask`); returns the box surfels left after each wall frame.
std::vector<size_t> take_the_box_away(SurfelMap& map, int frames, const cv::Mat& mask = {}) {
    const View with_box =
        render(Scene{{kWall}, {kBox}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    const View bare_wall =
        render(Scene{{kWall}, {}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    std::vector<size_t> left;
    for (int frame = 0; frame < kBoxFrames; ++frame) {
        const auto stats = fuse(map, with_box, frame);
        if (!stats.is_ok()) return ADD_FAILURE() << stats.status().to_string(), left;
        EXPECT_EQ(stats->removed_free_space + stats->weakened_free_space, 0u) << frame;
    }
    for (int frame = kBoxFrames; frame < kBoxFrames + frames; ++frame) {
        const auto stats = fuse(map, bare_wall, frame, mask);
        if (!stats.is_ok()) return ADD_FAILURE() << stats.status().to_string(), left;
        left.push_back(box_surfels(map));
    }
    return left;
}

TEST(FreeSpace, SurfelsTheCameraSeesThroughAreWeakenedThenRemoved) {
    SurfelMap map;
    const View with_box =
        render(Scene{{kWall}, {kBox}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    for (int frame = 0; frame < kBoxFrames; ++frame)
        ASSERT_TRUE(fuse(map, with_box, frame).is_ok());
    const size_t box_before = box_surfels(map);
    const size_t wall_before = wall_surfels(map);
    ASSERT_GT(box_before, 1500u);
    size_t stable_box = 0;
    for (const Surfel& s : map.surfels()) stable_box += s.position.z() < 1.8f && map.is_stable(s);
    ASSERT_EQ(stable_box, box_before);

    const View bare_wall =
        render(Scene{{kWall}, {}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    // First frame without the box: stable surfels lose confidence but stay.
    const auto first = fuse(map, bare_wall, kBoxFrames);
    ASSERT_TRUE(first.is_ok());
    EXPECT_EQ(first->weakened_free_space, box_before);
    EXPECT_EQ(first->removed_free_space, 0u);
    EXPECT_EQ(box_surfels(map), box_before);
    int frame = kBoxFrames + 1;
    for (; frame < kBoxFrames + 30 && box_surfels(map) > 0; ++frame) {
        const auto stats = fuse(map, bare_wall, frame);
        ASSERT_TRUE(stats.is_ok());
    }
    EXPECT_EQ(box_surfels(map), 0u) << "after " << frame - kBoxFrames << " frames";
    // Confidence 20 x weight (weight < 1) loses one weight a frame: at least 10 frames.
    EXPECT_GE(frame - kBoxFrames, 10);
    // The wall stays, and has grown where the box hid it.
    EXPECT_GE(wall_surfels(map), wall_before);
}

TEST(FreeSpace, DisabledSwitchKeepsTheBox) {
    SurfelMapConfig config;
    config.remove_free_space = false;
    SurfelMap kept(config);
    const std::vector<size_t> left = take_the_box_away(kept, 30);
    EXPECT_EQ(left.front(), left.back());
    EXPECT_GT(left.back(), 1500u);

    SurfelMap removed;
    const std::vector<size_t> gone = take_the_box_away(removed, 30);
    EXPECT_EQ(gone.back(), 0u);
    // Free-space removal took only the box: the wall fused with it is the same in both maps.
    // (Where the kept box hides the wall from association, each frame adds a new unstable wall
    // surfel there, so the totals differ.)
    const auto old_wall = [](const SurfelMap& map) {
        return std::count_if(map.surfels().begin(), map.surfels().end(), [](const Surfel& s) {
            return s.position.z() > 1.8f && s.init_frame < kBoxFrames;
        });
    };
    EXPECT_GT(old_wall(kept), kWidth * kHeight / 2);
    EXPECT_EQ(old_wall(removed), old_wall(kept));
}

TEST(FreeSpace, MaskedPixelsProveNothing) {
    // The box's pixels (and a 3-pixel border) are masked in the frames without it.
    const View with_box =
        render(Scene{{kWall}, {kBox}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    cv::Mat mask(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    for (int v = 0; v < kHeight; ++v) {
        for (int u = 0; u < kWidth; ++u) {
            if (with_box.vertex.at<cv::Vec3f>(v, u)[2] < 1.8f) {
                mask(cv::Rect(u - 3, v - 3, 7, 7) & cv::Rect(0, 0, kWidth, kHeight)).setTo(255);
            }
        }
    }
    SurfelMap map;
    const std::vector<size_t> left = take_the_box_away(map, 30, mask);
    EXPECT_GT(left.front(), 1500u);
    EXPECT_EQ(left.back(), left.front());
}

TEST(FreeSpace, StaticSceneSeenFromMovingPosesLosesNothing) {
    // Box edges seen from poses a pixel or two apart: a surfel on the silhouette may project
    // onto the wall behind, but its window still holds box pixels, so it is not punished.
    const Scene scene{{kWall}, {kBox}};
    for (const int window : {2, 0}) {
        SurfelMapConfig config;
        config.free_space_window_px = window;
        // Association by the pixel's own surfel only, so that silhouette pixels a pixel off
        // make new surfels whose free-space test the window has to settle.
        config.association_window_px = 0;
        SurfelMap map(config);
        size_t punished = 0;
        for (int frame = 0; frame < 30; ++frame) {
            const float s = 0.01f * static_cast<float>(frame % 5 - 2);  // +-2 cm: +-2 px
            Eigen::Isometry3f world_T_camera = Eigen::Isometry3f::Identity();
            world_T_camera.translation() = Eigen::Vector3f(s, -0.5f * s, 0.f);
            const View view = render(scene, world_T_camera, kWidth, kHeight);
            const auto stats = fuse(map, view, frame, {}, world_T_camera);
            ASSERT_TRUE(stats.is_ok());
            punished += stats->weakened_free_space + stats->removed_free_space;
        }
        if (window == 2) {
            EXPECT_EQ(punished, 0u);
        } else {
            EXPECT_GT(punished, 0u);  // the window is what protects the silhouette
        }
    }
}

TEST(FreeSpace, SurfelsBehindTheMeasuredSurfaceAreKept) {
    // The box appears in front of a fused wall: the wall is occluded, not seen through.
    SurfelMap map;
    const View bare_wall =
        render(Scene{{kWall}, {}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    const View with_box =
        render(Scene{{kWall}, {kBox}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    for (int frame = 0; frame < 5; ++frame) ASSERT_TRUE(fuse(map, bare_wall, frame).is_ok());
    const size_t wall = map.size();
    for (int frame = 5; frame < 15; ++frame) {
        const auto stats = fuse(map, with_box, frame);
        ASSERT_TRUE(stats.is_ok());
        EXPECT_EQ(stats->removed_free_space + stats->weakened_free_space, 0u);
    }
    EXPECT_EQ(wall_surfels(map), wall);
    EXPECT_GT(box_surfels(map), 1500u);
}

}  // namespace
}  // namespace df::map

namespace df::map {
namespace {

TEST(FreeSpace, CarvingAloneRemovesWhatTheFrameSeesThroughAndCanSpareTheStable) {
    // An object map's carve(): the box's map, the box gone, nothing fused.
    const View with_box =
        render(Scene{{kWall}, {kBox}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    const View bare_wall =
        render(Scene{{kWall}, {}}, Eigen::Isometry3f::Identity(), kWidth, kHeight);
    SurfelMap map;
    for (int frame = 0; frame < kBoxFrames; ++frame)
        ASSERT_TRUE(fuse(map, with_box, frame).is_ok());
    // Two unstable surfels beside the stable box: seen once, at the box's depth.
    const size_t stable_box = box_surfels(map);
    SurfelMap unstable_added = map;
    cv::Mat one_pixel(with_box.vertex.size(), CV_8UC1, cv::Scalar(255));
    one_pixel(cv::Rect(10, 10, 2, 1)).setTo(0);
    View near = with_box;
    near.vertex(cv::Rect(10, 10, 2, 1)).setTo(cv::Vec3f(0.f, 0.f, 0.f));
    for (int u = 10; u < 12; ++u) {  // 1.3 m along the pixel's ray: in front of the wall
        const io::Intrinsics k = intrinsics_for(kWidth, kHeight);
        near.vertex.at<cv::Vec3f>(10, u) = {static_cast<float>((u - k.cx) / k.fx * 1.3),
                                            static_cast<float>((10 - k.cy) / k.fy * 1.3), 1.3f};
    }
    ASSERT_TRUE(fuse(unstable_added, near, kBoxFrames, one_pixel).is_ok());
    ASSERT_EQ(unstable_added.size(), map.size() + 2);

    // keep_stable: only the two unstable surfels go.
    auto spared = unstable_added.carve(bare_wall.vertex, {}, Eigen::Isometry3f::Identity(),
                                       intrinsics_for(kWidth, kHeight), kBoxFrames + 1, true);
    ASSERT_TRUE(spared.is_ok()) << spared.status().to_string();
    EXPECT_EQ(spared->removed_free_space, 2u);
    EXPECT_EQ(spared->weakened_free_space, 0u);
    EXPECT_EQ(box_surfels(unstable_added), stable_box);
    // Without it the stable box is weakened, then removed within 30 frames; nothing is created.
    int frame = kBoxFrames + 1;
    for (; frame < kBoxFrames + 40 && box_surfels(map) > 0; ++frame) {
        auto carved = map.carve(bare_wall.vertex, {}, Eigen::Isometry3f::Identity(),
                                intrinsics_for(kWidth, kHeight), frame);
        ASSERT_TRUE(carved.is_ok());
        EXPECT_LE(carved->total, map.size());
    }
    EXPECT_EQ(box_surfels(map), 0u);
    // A mask makes the frame prove nothing.
    SurfelMap masked = unstable_added;
    const cv::Mat everything(with_box.vertex.size(), CV_8UC1, cv::Scalar(255));
    auto none = masked.carve(bare_wall.vertex, everything, Eigen::Isometry3f::Identity(),
                             intrinsics_for(kWidth, kHeight), kBoxFrames + 1);
    ASSERT_TRUE(none.is_ok());
    EXPECT_EQ(none->removed_free_space + none->weakened_free_space, 0u);
}

}  // namespace
}  // namespace df::map
