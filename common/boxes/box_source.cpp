#include "boxes/box_source.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "config/apply_params.hpp"
#include "detect/detector.hpp"
#include "eval/segmentation.hpp"
#include "io/tum/stamp.hpp"
#include "sim/simulated_detector.hpp"

namespace df::boxes {
namespace {

class YoloSource : public BoxSource {
  public:
    explicit YoloSource(std::unique_ptr<detect::Detector> d) : detector_(std::move(d)) {}
    Result<std::vector<detect::Detection>> detect(const io::RgbdImage& image, uint64_t) override {
        return detector_->detect(image.rgb, detect::ColorOrder::kRgb);  // frames carry R,G,B
    }
    std::string describe() const override {
        const auto& c = detector_->config();
        return "YOLO " + (c.model_path.empty() ? detect::default_yolov5_dir() : c.model_path) +
               " at " + std::to_string(c.input_width) + "x" + std::to_string(c.input_height);
    }

  private:
    std::unique_ptr<detect::Detector> detector_;
};

/// SIMULATED: boxes from the sequence's instances/<stamp>.png and instances.json.
class SimulatedSource : public BoxSource {
  public:
    SimulatedSource(std::string folder, std::vector<sim::ObjectClass> classes,
                    sim::SimulatedDetectorConfig config)
        : folder_(std::move(folder)), classes_(std::move(classes)), config_(config) {}
    Result<std::vector<detect::Detection>> detect(const io::RgbdImage& image,
                                                  uint64_t seq) override {
        const std::string file = folder_ + "/instances/" + io::stamp_text(image.sensor_ns) + ".png";
        const cv::Mat instance = cv::imread(file, cv::IMREAD_UNCHANGED);
        if (instance.empty() || instance.type() != CV_16UC1) {
            return error(StatusCode::kNotFound,
                         "simulated detector: no 16-bit instance image " + file);
        }
        if (config_.latency_ms > 0) {
            std::this_thread::sleep_for(
                std::chrono::duration<double, std::milli>(config_.latency_ms));
        }
        auto boxes = sim::simulate_detections(instance, classes_, static_cast<int>(seq), config_);
        // In the pixels of the image given (the reduced colour image on color_small).
        const float sx = static_cast<float>(image.rgb.cols) / static_cast<float>(instance.cols);
        const float sy = static_cast<float>(image.rgb.rows) / static_cast<float>(instance.rows);
        for (detect::Detection& d : boxes) {
            d.box = cv::Rect2f(d.box.x * sx, d.box.y * sy, d.box.width * sx, d.box.height * sy);
        }
        return boxes;
    }
    std::string describe() const override {
        return "SIMULATED detector on the ground truth of " + folder_;
    }

  private:
    std::string folder_;
    std::vector<sim::ObjectClass> classes_;
    sim::SimulatedDetectorConfig config_;
};

}  // namespace

Result<std::unique_ptr<BoxSource>> open_source(const config::DetectorServiceConfig& c) {
    if (c.model() == "simulated") {
        if (c.sim_sequence().empty() || !std::filesystem::is_directory(c.sim_sequence())) {
            return error(
                StatusCode::kNotFound,
                "model \"simulated\" needs sim_sequence: a generated sequence folder, got \"" +
                    c.sim_sequence() + "\"");
        }
        auto instances = eval::read_instances_json(c.sim_sequence() + "/instances.json");
        if (!instances) return instances.status();
        std::vector<sim::ObjectClass> classes;
        for (const eval::GtInstance& g : *instances) {
            if (g.id < 1) continue;
            if (classes.size() < static_cast<size_t>(g.id))
                classes.resize(static_cast<size_t>(g.id));
            classes[static_cast<size_t>(g.id) - 1] = {g.class_id, g.class_name};
        }
        sim::SimulatedDetectorConfig s;
        s.miss_rate = c.sim_miss_rate();
        s.false_positives_per_frame = c.sim_false_positives_per_frame();
        s.box_jitter = c.sim_box_jitter();
        s.latency_ms = c.sim_latency_ms();
        s.seed = c.sim_seed();
        return std::unique_ptr<BoxSource>(new SimulatedSource(c.sim_sequence(), classes, s));
    }
    detect::DetectorConfig d;
    if (c.model() == "yolov5") {
        d.kind = detect::ModelKind::kTfjsYolov5;
    } else if (c.model() == "darknet") {
        d.kind = detect::ModelKind::kDarknet;
    } else if (c.model() == "onnx") {
        d.kind = detect::ModelKind::kOnnx;
    } else {
        return error(StatusCode::kInvalidArgument,
                     "model must be yolov5, darknet, onnx or simulated, got \"" + c.model() + "\"");
    }
    d.model_path = c.model_path();
    d.weights_path = c.weights_path();
    d.names_path = c.names_path();
    DF_RETURN_IF_ERROR(config::apply_params(c, &d));  // the (params_struct) fields
    const auto& names = detect::coco_names();
    for (const auto& [name, threshold] : c.class_score_thresholds()) {
        if (d.names_path.empty() && std::find(names.begin(), names.end(), name) == names.end()) {
            return error(StatusCode::kInvalidArgument,
                         "class_score_thresholds: '" + name + "' is not a COCO class name");
        }
        d.class_score_thresholds[name] = threshold;
    }
    auto detector = detect::open_detector(d);
    if (!detector) return detector.status();
    return std::unique_ptr<BoxSource>(new YoloSource(std::move(*detector)));
}

}  // namespace df::boxes
