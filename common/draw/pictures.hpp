#pragma once
/// Pictures for people to look at: detector boxes with class and score, object instances tinted
/// by kind with their boxes and names, geometric segments in a colour each. Every function draws
/// on (or returns) an 8-bit 3-channel picture in R,G,B order unless it says otherwise. DDS-free.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/detection.hpp"
#include "dynamics/frame_segments.hpp"

namespace df::draw {

/// The tint of a kind, R,G,B: persons (non-rigid) red, rigid objects blue, unknown movers yellow.
cv::Scalar kind_tint(dynamics::ObjectKind kind);

/// The COCO name of class_id ("object" outside 0..79).
std::string class_name(int class_id);

/// A colour of its own per id (hues spread, three brightnesses), R,G,B.
cv::Vec3b id_colour(int id);

/// Draws each detection on `image` (3 channels, in `bgr` order or R,G,B): its box, and its class
/// and score on a filled label above it, kept inside the picture; one colour per class.
void draw_detections(const std::vector<detect::Detection>& detections, bool bgr, cv::Mat* image);

/// Tints the pixels of every instance of `labels` with its kind's tint (half and half) and draws
/// its box (scaled by `box_scale`, for labels made at a lower resolution) and its name: class and
/// score, or "unknown mover". Labels of another size than `rgb` are scaled (nearest).
void tint_instances(const dynamics::LabelImage& labels, float box_scale, cv::Mat* rgb);

/// Geometric segments (CV_32SC1 or CV_16UC1, 0 = none) as a picture: a colour per segment,
/// black where there is none. With `rgb` (same size) given, the colours are blended over it.
cv::Mat colour_segments(const cv::Mat& labels, const cv::Mat& rgb = cv::Mat());

}  // namespace df::draw
