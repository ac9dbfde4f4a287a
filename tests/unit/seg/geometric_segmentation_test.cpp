// Geometric segmentation: the normal sign convention on analytic folds (concave is an edge,
// convex is not), depth steps, bad input; and on generated sequences, how well segments cover
// the ground-truth objects.
#include "seg/geometric_segmentation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "seg_test_frames.hpp"
#include "slam/depth_maps.hpp"

namespace df::seg {
namespace {

constexpr int kW = 160, kH = 120;
const io::Intrinsics kK{140.0, 140.0, 79.5, 59.5};

struct Plane {
    Eigen::Vector3d n;  // any orientation; plane n . p = d
    double d;
};

// Depth of the surface the camera at the origin sees: the nearest plane (inside of a room,
// concave) or the farthest (a solid's convex ridge seen from outside).
cv::Mat depth_of(const std::vector<Plane>& planes, bool convex) {
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(0));
    for (int v = 0; v < kH; ++v) {
        for (int u = 0; u < kW; ++u) {
            const Eigen::Vector3d ray((u - kK.cx) / kK.fx, (v - kK.cy) / kK.fy, 1.0);
            double best = convex ? 0.0 : 1e9;
            for (const Plane& p : planes) {
                const double t = p.d / p.n.dot(ray);
                if (!(t > 0)) continue;
                best = convex ? std::max(best, t) : std::min(best, t);
            }
            if (best > 0 && best < 1e8) depth.at<float>(v, u) = static_cast<float>(best);
        }
    }
    return depth;
}

GeometricSegmentation segment_depth(const cv::Mat& depth) {
    const cv::Mat vertex = slam::compute_vertex_map(depth, kK);
    const cv::Mat normal = slam::compute_normal_map(depth, kK);
    auto s = segment_geometry(vertex, normal);
    EXPECT_TRUE(s.is_ok()) << s.status().message();
    return s.is_ok() ? *s : GeometricSegmentation{};
}

// Fraction of the pixels in column band [u0, u1) that are edges.
double edge_fraction(const cv::Mat& edges, int u0, int u1) {
    return cv::countNonZero(edges(cv::Rect(u0, 2, u1 - u0, kH - 4))) /
           static_cast<double>((u1 - u0) * (kH - 4));
}

// Fraction of the rows (away from the border) with an edge pixel in column band [u0, u1).
double rows_with_edge(const cv::Mat& edges, int u0, int u1) {
    int rows = 0;
    for (int v = 2; v < kH - 2; ++v)
        rows += cv::countNonZero(edges(cv::Rect(u0, v, u1 - u0, 1))) > 0;
    return rows / static_cast<double>(kH - 4);
}

TEST(GeometricSegmentation, ConcaveFoldIsAnEdgeAndSplitsTwoSegments) {
    // The inside of a vertical corner: two walls at 45 degrees meeting at x = 0, z = 2.
    const double s = std::sqrt(0.5);
    const cv::Mat depth = depth_of({{{s, 0, s}, 2 * s}, {{-s, 0, s}, 2 * s}}, false);
    const GeometricSegmentation g = segment_depth(depth);
    EXPECT_GT(rows_with_edge(g.edges, 77, 83), 0.95) << "the crease is an edge";
    EXPECT_LT(edge_fraction(g.edges, 10, 60), 0.01) << "plain wall is no edge";
    EXPECT_EQ(g.count, 2);
    EXPECT_NE(g.labels.at<int32_t>(60, 30), g.labels.at<int32_t>(60, 130));
}

TEST(GeometricSegmentation, ConvexFoldIsNotAnEdge) {
    // The same two planes seen as a solid's ridge pointing at the camera.
    const double s = std::sqrt(0.5);
    const cv::Mat depth = depth_of({{{s, 0, s}, 2 * s}, {{-s, 0, s}, 2 * s}}, true);
    const GeometricSegmentation g = segment_depth(depth);
    EXPECT_LT(rows_with_edge(g.edges, 70, 90), 0.05) << "a convex fold is not an edge";
    EXPECT_EQ(g.count, 1);
}

TEST(GeometricSegmentation, DepthStepIsAnEdgeAndSeparatesTheObject) {
    cv::Mat depth(kH, kW, CV_32F, cv::Scalar(2.5f));
    depth(cv::Rect(50, 30, 60, 50)).setTo(1.5f);  // a box face 1 m in front of the wall
    const GeometricSegmentation g = segment_depth(depth);
    EXPECT_EQ(g.count, 2);
    const int box = g.labels.at<int32_t>(55, 80), wall = g.labels.at<int32_t>(10, 10);
    EXPECT_GT(box, 0);
    EXPECT_GT(wall, 0);
    EXPECT_NE(box, wall);
    // Edge pixels re-absorbed: the box label covers its face up to about a pixel.
    int box_pixels = 0;
    for (int v = 0; v < kH; ++v)
        for (int u = 0; u < kW; ++u) box_pixels += g.labels.at<int32_t>(v, u) == box;
    EXPECT_GE(box_pixels, 56 * 46);
    EXPECT_LE(box_pixels, 60 * 50);
}

TEST(GeometricSegmentation, BadInputIsAnError) {
    const cv::Mat v(10, 10, CV_32FC3, cv::Scalar::all(1)), n(10, 11, CV_32FC3);
    EXPECT_FALSE(segment_geometry(v, n).is_ok());
    EXPECT_FALSE(segment_geometry(cv::Mat(10, 10, CV_32FC1), cv::Mat(10, 10, CV_32FC1)).is_ok());
    GeometricSegmentationConfig bad;
    bad.min_segment_pixels = 0;
    auto r = segment_geometry(v, v, bad);
    ASSERT_FALSE(r.is_ok());
    EXPECT_NE(r.status().message().find("min_segment_pixels"), std::string::npos);
}

TEST(GeometricSegmentation, CoversGeneratedObjectsWithoutStraddlingTheirSilhouettes) {
    // Generated sequences with sensor noise: for every visible object, the best segment's IoU
    // with its ground-truth mask; and segments on objects keep to the object.
    double iou_sum = 0.0;
    int objects = 0, straddling = 0, object_segments = 0, across_steps = 0;
    for (const char* preset : {"default", "room4", "walking_xyz"}) {
        const test::SegFrames frames = test::seg_frames(preset, {20, 50, 80, 110});
        for (const test::SegFrame& f : frames.frames) {
            auto g = segment_geometry(f.vertex, f.normal);
            ASSERT_TRUE(g.is_ok()) << g.status().message();
            const auto [ious, impure] = test::best_segment_ious(g->labels, g->count, f.instance);
            for (const auto& [id, iou] : ious) {
                const double z = test::median_depth(f.instance, f.depth_m, id);
                std::printf("%s frame %d %s at %.1f m: best segment IoU %.2f%s\n", preset, f.index,
                            frames.names.at(id).c_str(), z, iou,
                            z > test::kMaxScoredDepthM ? " (too far, not scored)" : "");
                if (z > test::kMaxScoredDepthM) continue;
                iou_sum += iou;
                ++objects;
            }
            straddling += impure.first;
            across_steps += test::segments_across_depth_steps(g->labels, f.instance, f.depth_m);
            object_segments += impure.second;
        }
    }
    ASSERT_GT(objects, 6);
    const double mean = iou_sum / objects;
    std::printf(
        "mean best-segment IoU over %d object views: %.3f; segments straddling an "
        "object silhouette: %d of %d\n",
        objects, mean, straddling, object_segments);
    EXPECT_GT(mean, 0.5);  // measured 0.597 (docs/segmentation.md)
    EXPECT_LE(straddling, object_segments / 10);
    std::printf("segments across a depth step between an object and what is behind it: %d\n",
                across_steps);
    EXPECT_EQ(across_steps, 0);
}

}  // namespace
}  // namespace df::seg
