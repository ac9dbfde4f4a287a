/// COCO names, default model locations and the DetectorConfig helpers.
#include <cstdlib>

#include "detect/detector.hpp"

namespace df::detect {

const std::vector<std::string>& coco_names() {
    // darknet's data/coco.names order (the order YOLOv5's and YOLOv3's COCO heads use).
    static const std::vector<std::string> names = {
        "person",        "bicycle",       "car",           "motorbike",
        "aeroplane",     "bus",           "train",         "truck",
        "boat",          "traffic light", "fire hydrant",  "stop sign",
        "parking meter", "bench",         "bird",          "cat",
        "dog",           "horse",         "sheep",         "cow",
        "elephant",      "bear",          "zebra",         "giraffe",
        "backpack",      "umbrella",      "handbag",       "tie",
        "suitcase",      "frisbee",       "skis",          "snowboard",
        "sports ball",   "kite",          "baseball bat",  "baseball glove",
        "skateboard",    "surfboard",     "tennis racket", "bottle",
        "wine glass",    "cup",           "fork",          "knife",
        "spoon",         "bowl",          "banana",        "apple",
        "sandwich",      "orange",        "broccoli",      "carrot",
        "hot dog",       "pizza",         "donut",         "cake",
        "chair",         "sofa",          "pottedplant",   "bed",
        "diningtable",   "toilet",        "tvmonitor",     "laptop",
        "mouse",         "remote",        "keyboard",      "cell phone",
        "microwave",     "oven",          "toaster",       "sink",
        "refrigerator",  "book",          "clock",         "vase",
        "scissors",      "teddy bear",    "hair drier",    "toothbrush"};
    return names;
}

std::string default_models_dir() {
    if (const char* dir = std::getenv("DF_MODELS_DIR"); dir != nullptr && *dir != '\0') {
        return dir;
    }
    const char* home = std::getenv("HOME");
    return std::string(home != nullptr ? home : ".") + "/.cache/detectfusion/models";
}

std::string default_yolov5_dir() { return default_models_dir() + "/yolov5s"; }

ClassKind DetectorConfig::kind_of(const std::string& class_name) const {
    if (non_rigid_classes.count(class_name) != 0) return ClassKind::kNonRigid;
    if (rigid_classes.count(class_name) != 0) return ClassKind::kRigid;
    return ClassKind::kIgnored;
}

float DetectorConfig::threshold_for(const std::string& class_name) const {
    auto it = class_score_thresholds.find(class_name);
    return it != class_score_thresholds.end() ? it->second : score_threshold;
}

}  // namespace df::detect
