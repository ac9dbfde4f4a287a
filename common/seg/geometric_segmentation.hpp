#pragma once
/// Geometric segmentation of a depth image (Tateno et al. 2015, as MaskFusion and DetectFusion
/// use it): per-pixel edge strength from normal concavity and depth discontinuity over the
/// neighbours (4 by default, the anchors' 8 as an option), a threshold, 4-connected components of
/// the non-edge pixels, a minimum segment size, and edge pixels re-absorbed into an adjacent
/// segment of nearly the same depth. DDS-free; works on the vertex and normal maps of one camera
/// frame.
///
/// Normal convention (pinned by a test): normals point towards the camera (n . v < 0), as
/// df_slam's preprocessing makes them. For a neighbour v_k of v, (v_k - v) . n < 0 means v_k lies
/// behind the tangent plane as seen from the camera: the surface bends away, a convex fold, which
/// is not an edge. Otherwise the fold is concave (the inside of a room corner, where an object
/// meets the floor) and its strength is 1 - n_k . n.
#include <opencv2/core.hpp>
#include <string>

#include "core/status.hpp"

namespace df::seg {

/// Every threshold; defaults after MaskFusion (FACTS.md §5) unless noted.
struct GeometricSegmentationConfig {
    /// The anchors mark an edge where min(1, max(wC concavity, wD distance)) > 0.1. Written as
    /// two thresholds: concavity (1 - cos of the fold angle) above this is an edge ...
    float max_concavity = 0.1f;  ///< 0.1: folds sharper than about 26 degrees (at z = 0)
    /// Growth of the concavity threshold with depth (per metre^2): normals of noisy far depth
    /// disagree by more (0.03: 0.22 at 2 m, 0.37 at 3 m; the anchors use a constant, which
    /// turned a person at 3 m into edges alone on Kinect-like noise).
    float max_concavity_per_m2 = 0.03f;
    /// ... and a neighbour farther than this from the pixel's tangent plane (metres) is across a
    /// depth discontinuity. The second term grows the tolerance with depth noise (~z^2 for
    /// structured-light and ToF sensors); the anchors use a constant.
    float max_distance_m = 0.01f;
    float max_distance_per_m2 = 0.002f;  ///< metres per metre^2 of depth (2.8 cm at 3 m)
    /// Components smaller than this (pixels, before re-absorption) are left unlabelled.
    int min_segment_pixels = 160;
    /// Edge pixels join an adjacent segment whose pixel depth differs by less than this (metres).
    float absorb_max_depth_difference_m = 0.008f;
    /// Neighbours each pixel is compared with: 8 (the anchors) or 4 (the direct ones only). 4
    /// is the default: 13 ms instead of 18 ms per 640x480 frame on one core, and on the
    /// generated sequences slightly better (best-segment IoU 0.59 vs 0.565, object masks 0.725
    /// vs 0.712), thinner edges losing fewer object pixels.
    int neighbours = 4;
    /// Re-absorption passes (each grows segments by one pixel into the edges).
    int absorb_iterations = 2;
};

/// Empty when valid, else what is wrong.
std::string validate(const GeometricSegmentationConfig& config);

struct GeometricSegmentation {
    cv::Mat edges;   ///< CV_8UC1, 255 = edge pixel (including invalid depth), 0 = surface
    cv::Mat labels;  ///< CV_32SC1, segment 1..count, 0 = none (edge, invalid or too small)
    int count = 0;   ///< number of segments
};

/// Segments one frame.
/// - vertex: CV_32FC3, camera frame, metres; invalid where z <= 0 or not finite.
/// - normal: CV_32FC3, unit, towards the camera; invalid where (0,0,0).
/// Both must have the same size. Runs on the calling thread only.
Result<GeometricSegmentation> segment_geometry(const cv::Mat& vertex, const cv::Mat& normal,
                                               const GeometricSegmentationConfig& config = {});

}  // namespace df::seg
