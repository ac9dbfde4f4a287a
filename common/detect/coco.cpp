/// COCO names, default model locations and the DetectorConfig helpers.
#include <unistd.h>

#include <algorithm>
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

std::vector<std::string> models_search_path() {
    std::vector<std::string> dirs;
    if (const char* dir = std::getenv("DF_MODELS_DIR"); dir != nullptr && *dir != '\0') {
        dirs.emplace_back(dir);
    }
    if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
        dirs.push_back(std::string(home) + "/.cache/detectfusion/models");
    }
    dirs.emplace_back(kSystemModelsDir);
    return dirs;
}

std::string default_models_dir() {
    const auto dirs = models_search_path();
    for (const auto& d : dirs) {
        if (::access(d.c_str(), R_OK | X_OK) == 0) return d;
    }
    return std::getenv("DF_MODELS_DIR") != nullptr && *std::getenv("DF_MODELS_DIR") != '\0'
               ? dirs.front()
               : std::string(kSystemModelsDir);
}

std::string default_yolov5_dir() {
    for (const auto& d : models_search_path()) {
        const std::string folder = d + "/yolov5s";
        // Readable by this user: a model under another user's home does not count.
        if (::access((folder + "/model.json").c_str(), R_OK) == 0) return folder;
    }
    return default_models_dir() + "/yolov5s";
}

ClassKind class_kind(const params::fusion::ClassParams& classes, const std::string& class_name) {
    const auto has = [&class_name](const std::vector<std::string>& list) {
        return std::find(list.begin(), list.end(), class_name) != list.end();
    };
    if (has(classes.non_rigid)) return ClassKind::kNonRigid;
    if (has(classes.rigid)) return ClassKind::kRigid;
    return ClassKind::kIgnored;
}

Status check_class_names(const params::fusion::ClassParams& classes) {
    const auto& names = coco_names();
    for (const auto* list : {&classes.rigid, &classes.non_rigid}) {
        for (const std::string& n : *list) {
            if (std::find(names.begin(), names.end(), n) == names.end()) {
                return error(StatusCode::kInvalidArgument,
                             "class '" + n + "' is not a COCO class name (see coco.names)");
            }
        }
    }
    return Status::ok();
}

ClassKind DetectorConfig::kind_of(const std::string& class_name) const {
    return class_kind(classes, class_name);
}

float DetectorConfig::threshold_for(const std::string& class_name) const {
    auto it = class_score_thresholds.find(class_name);
    return it != class_score_thresholds.end() ? it->second : score_threshold;
}

}  // namespace df::detect
