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
#include "params/geoseg_params.hpp"

namespace df::seg {

/// Every threshold; defaults after MaskFusion (FACTS.md §5) unless noted.
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/geoseg.proto (GeosegParams), and generated into params/geoseg_params.hpp;
/// max_depth_m and normal_baseline_px are the depth preprocessing the caller runs first
/// (segment_depth in seg/frame_segmenter.hpp, the geoseg service).
using GeometricSegmentationConfig = params::geoseg::GeosegParams;

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
