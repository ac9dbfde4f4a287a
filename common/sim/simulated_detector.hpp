#pragma once
/// SIMULATED detector: boxes read from the ground-truth instance image of a generated sequence,
/// so that segmentation and the rest of the pipeline can be scored against truth without a
/// learned model. It knows the scene's objects by class; objects of unknown class (class_id -1)
/// are never detected, as a COCO detector would not. Misses, false positives and box jitter are
/// configurable and drawn from a seeded generator (same seed and frame, same boxes); latency is
/// for the caller (the detector service) to apply. The real detector is df_detect (YOLO).
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/detection.hpp"
#include "sim/scene.hpp"

namespace df::sim {

struct SimulatedDetectorConfig {
    double miss_rate = 0.0;                ///< probability that a visible object is not reported
    double false_positives_per_frame = 0;  ///< mean of a Poisson count of random boxes per frame
    double box_jitter = 0.0;       ///< each box edge moves by N(0, jitter * box size), fraction
    int min_visible_pixels = 200;  ///< objects showing fewer pixels are not reported
    double score = 0.9;            ///< score of true detections (false positives: 0.3..0.6)
    double latency_ms = 0.0;       ///< added delay the detector service waits before answering
    uint64_t seed = 1;
};

/// The class of instance id k + 1 (what instances.json lists).
struct ObjectClass {
    int class_id = -1;  ///< COCO index; -1: unknown (never detected)
    std::string class_name;
};

/// Boxes of the objects visible in `instance` (CV_16UC1, 0 = static scene, k = classes[k - 1]).
std::vector<detect::Detection> simulate_detections(const cv::Mat& instance,
                                                   const std::vector<ObjectClass>& classes,
                                                   int frame,
                                                   const SimulatedDetectorConfig& config);

/// Boxes of the objects visible in `instance` (CV_16UC1, 0 = static scene, k = objects[k - 1],
/// as sim::render writes it) for frame `frame`. False positives take a random COCO class of the
/// scene's known classes (or "chair" when it has none).
std::vector<detect::Detection> simulate_detections(const cv::Mat& instance,
                                                   const std::vector<DynamicObject>& objects,
                                                   int frame,
                                                   const SimulatedDetectorConfig& config);

}  // namespace df::sim
