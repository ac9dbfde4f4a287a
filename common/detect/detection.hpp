#pragma once
/// What every detector returns (YOLO through OpenCV's dnn module, or the simulated detector of
/// df_sim): axis-aligned boxes in pixels of the image the detector was given, with a COCO class
/// and a score. DDS-free.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace df::detect {

/// How a detected class is treated downstream (DetectFusion: rigid objects get their own map and
/// pose, non-rigid ones, persons by default, are only masked out).
enum class ClassKind { kRigid, kNonRigid, kIgnored };

struct Detection {
    cv::Rect2f box;          ///< pixels, x right, y down; (x, y) top-left corner
    int class_id = -1;       ///< COCO index 0..79 in darknet's coco.names order
    std::string class_name;  ///< "person", "car", ...
    float score = 0.f;       ///< 0..1 (objectness times class probability for YOLO)
};

}  // namespace df::detect
