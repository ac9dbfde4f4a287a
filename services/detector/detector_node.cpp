#include "detector_node.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "eval/segmentation.hpp"
#include "service/service.hpp"

namespace df::detector_service {
namespace {

int64_t now_ns() { return service::steady_ns(); }

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
        char name[64];
        std::snprintf(name, sizeof name, "%.6f.png", static_cast<double>(image.sensor_ns) * 1e-9);
        const std::string file = folder_ + "/instances/" + name;
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
    d.input_width = c.input_width();
    d.input_height = c.input_height();
    d.score_threshold = c.score_threshold();
    d.nms_iou_threshold = c.nms_iou_threshold();
    const auto& names = detect::coco_names();
    for (const auto& [name, threshold] : c.class_score_thresholds()) {
        if (d.names_path.empty() && std::find(names.begin(), names.end(), name) == names.end()) {
            return error(StatusCode::kInvalidArgument,
                         "class_score_thresholds: '" + name + "' is not a COCO class name");
        }
        d.class_score_thresholds[name] = threshold;
    }
    d.threads = c.threads();
    auto detector = detect::open_detector(d);
    if (!detector) return detector.status();
    return std::unique_ptr<BoxSource>(new YoloSource(std::move(*detector)));
}

Result<std::unique_ptr<DetectorNode>> DetectorNode::create(
    const config::DetectorServiceConfig& config, std::unique_ptr<BoxSource> source,
    dds::Participant& participant) {
    const std::string& ns = config.dds().ns();
    if (config.input() != "frames" && config.input() != "color_small") {
        return error(StatusCode::kInvalidArgument,
                     "input must be \"frames\" or \"color_small\", got \"" + config.input() + "\"");
    }
    auto waitset = dds::WaitSet::create(participant);
    if (!waitset) return waitset.status();
    std::optional<dds::Reader<df_msg_RgbdFrame>> frames;
    std::optional<dds::Reader<df_msg_CompressedImage>> small;
    if (config.input() == "frames") {
        auto r = dds::Reader<df_msg_RgbdFrame>::create(participant,
                                                       dds::topic_name(ns, dds::topics::kFrames));
        if (!r) return r.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(r->get()));
        frames.emplace(std::move(*r));
    } else {
        auto r = dds::Reader<df_msg_CompressedImage>::create(
            participant, dds::topic_name(ns, dds::topics::kColorSmall));
        if (!r) return r.status();
        DF_RETURN_IF_ERROR(waitset->attach_reader(r->get()));
        small.emplace(std::move(*r));
    }
    auto detections = dds::Writer<df_msg_Detections>::create(
        participant, dds::topic_name(ns, dds::topics::kDetections));
    if (!detections) return detections.status();
    auto status = dds::Writer<df_msg_StageStatus>::create(
        participant, dds::topic_name(ns, dds::topics::kStageStatus));
    if (!status) return status.status();
    return std::unique_ptr<DetectorNode>(
        new DetectorNode(config, std::move(source), std::move(frames), std::move(small),
                         std::move(*detections), std::move(*status), std::move(*waitset)));
}

DetectorNode::DetectorNode(const config::DetectorServiceConfig& config,
                           std::unique_ptr<BoxSource> source,
                           std::optional<dds::Reader<df_msg_RgbdFrame>> frames,
                           std::optional<dds::Reader<df_msg_CompressedImage>> small,
                           dds::Writer<df_msg_Detections> detections,
                           dds::Writer<df_msg_StageStatus> status, dds::WaitSet waitset)
    : config_(config),
      source_(std::move(source)),
      frames_(std::move(frames)),
      small_(std::move(small)),
      detections_(std::move(detections)),
      status_(std::move(status)),
      waitset_(std::move(waitset)) {}

void DetectorNode::answer(const df_msg_Header& header, df_msg_FrameStatus status,
                          const std::vector<detect::Detection>& boxes, int width, int height,
                          double ms) {
    df_msg_Detections m{};
    m.header = header;
    m.header.status = status;
    m.image_width = static_cast<uint16_t>(width);
    m.image_height = static_cast<uint16_t>(height);
    for (const detect::Detection& d : boxes) {
        if (m.count >= df_msg_MAX_DETECTIONS) break;
        df_msg_Detection& b = m.boxes[m.count++];
        b.x = d.box.x;
        b.y = d.box.y;
        b.w = d.box.width;
        b.h = d.box.height;
        b.class_id = d.class_id;
        b.score = d.score;
    }
    if (Status s = detections_.write_copy(m); !s) log::warn("seq=", header.seq, " ", s.message());
    df_msg_StageStatus st{};
    st.header = m.header;
    dds::set_name(st.stage, config_.stage());
    if (status == df_msg_FRAME_OK) {
        st.timing_count = 1;
        dds::set_name(st.timings[0].name, "detect");
        st.timings[0].ms = static_cast<float>(ms);
    }
    (void)status_.write_copy(st);
}

void DetectorNode::handle(const Pending& p) {
    const df_msg_Header& header = p.header;
    const uint32_t nth = std::max<uint32_t>(1, config_.every_nth());
    if (header.seq % nth != 0) {
        ++skipped_;
        answer(header, df_msg_FRAME_SKIPPED, {}, p.source_width, p.source_height, 0);
        return;
    }
    if (p.image.rgb.empty()) {
        ++failed_;
        log::error("seq=", header.seq, " undecodable colour image");
        answer(header, df_msg_FRAME_FAILED, {}, p.source_width, p.source_height, 0);
        return;
    }
    const int64_t t0 = now_ns();
    auto boxes = source_->detect(p.image, header.seq);
    const double ms = static_cast<double>(now_ns() - t0) * 1e-6;
    if (!boxes) {
        ++failed_;
        log::error("seq=", header.seq, " ", boxes.status().message());
        answer(header, df_msg_FRAME_FAILED, {}, p.source_width, p.source_height, ms);
        return;
    }
    // Back to the pixels of the full frame.
    const float sx = static_cast<float>(p.source_width) / static_cast<float>(p.image.rgb.cols);
    const float sy = static_cast<float>(p.source_height) / static_cast<float>(p.image.rgb.rows);
    for (detect::Detection& d : *boxes) {
        d.box = cv::Rect2f(d.box.x * sx, d.box.y * sy, d.box.width * sx, d.box.height * sy);
    }
    ++detected_;
    answer(header, df_msg_FRAME_OK, *boxes, p.source_width, p.source_height, ms);
}

Status DetectorNode::take(std::vector<Pending>* pending) {
    if (frames_) {
        auto taken = frames_->take(
            [&](const df_msg_RgbdFrame& f, const dds_sample_info_t& info) {
                if (!info.valid_data) return;
                Pending p{dds::to_image(f), f.header, 0, 0};
                p.source_width = p.image.rgb.cols;
                p.source_height = p.image.rgb.rows;
                pending->push_back(std::move(p));
            },
            16);
        return taken ? Status::ok() : taken.status();
    }
    auto taken = small_->take(
        [&](const df_msg_CompressedImage& m, const dds_sample_info_t& info) {
            if (!info.valid_data) return;
            Pending p;
            p.header = m.header;
            p.source_width = m.source_width;
            p.source_height = m.source_height;
            p.image.sensor_ns = static_cast<int64_t>(m.header.sensor_ns);
            const cv::Mat bytes(1, static_cast<int>(m.data._length), CV_8UC1, m.data._buffer);
            const cv::Mat bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
            if (!bgr.empty()) cv::cvtColor(bgr, p.image.rgb, cv::COLOR_BGR2RGB);
            pending->push_back(std::move(p));
        },
        16);
    return taken ? Status::ok() : taken.status();
}

uint32_t DetectorNode::matched_writers() const {
    return frames_ ? frames_->matched_writers() : small_->matched_writers();
}

Status DetectorNode::run() {
    log::info(source_->describe(), "; waiting for frames on ",
              frames_ ? frames_->topic() : small_->topic());
    service::StreamEnd stream(config_.idle_exit_s());
    while (!service::stop_requested()) {
        auto woke = waitset_.wait(DDS_MSECS(100));
        if (!woke) return woke.status();
        std::vector<Pending> pending;
        DF_RETURN_IF_ERROR(take(&pending));
        for (size_t i = 0; i < pending.size(); ++i) {
            stream.on_input();
            if (i + 1 < pending.size()) {  // stay current: answer the older ones skipped
                ++skipped_;
                answer(pending[i].header, df_msg_FRAME_SKIPPED, {}, pending[i].source_width,
                       pending[i].source_height, 0);
            } else {
                handle(pending[i]);
            }
        }
        if (const char* why = stream.check(matched_writers(), pending.empty())) {
            log::info("stream ended (", why, "): ", detected_, " frames detected, ", skipped_,
                      " skipped, ", failed_, " failed");
            if (config_.exit_at_end()) return Status::ok();
            stream.reset();
            detected_ = skipped_ = failed_ = 0;
        }
    }
    return Status::ok();
}

}  // namespace df::detector_service
