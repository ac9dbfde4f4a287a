// df_detector: 2D object detection on every frame (YOLO through OpenCV, or the SIMULATED
// detector on a generated sequence), as a DDS service (docs/segmentation.md); or, with --image,
// on picture files from the command line, without DDS.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "boxes/image_files.hpp"
#include "config/validate.hpp"
#include "core/log.hpp"
#include "detector_node.hpp"
#include "service/service.hpp"

namespace {

/// `df_detector --image FILE...`: prints the boxes of every picture and writes it with the boxes
/// drawn into out_dir. A bad picture is reported and the others still done; exit 1 if any failed.
int detect_images(df::boxes::BoxSource& source, const std::vector<std::string>& files,
                  const std::string& out_dir) {
    int failed = 0;
    for (const std::string& file : files) {
        auto result = df::boxes::detect_image_file(source, file, out_dir);
        if (!result) {
            df::log::error(result.status().message());
            ++failed;
            continue;
        }
        std::fputs(df::boxes::describe(*result).c_str(), stdout);
        std::fflush(stdout);
    }
    return failed > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("detector");
    CLI::App app{
        "df_detector: COCO object detection (YOLO, or simulated from ground truth) as a "
        "DDS service, or on picture files with --image"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    std::vector<std::string> images;
    std::string out_dir = ".";
    app.add_option("--image", images,
                   "detect on these picture files instead of serving frames (no DDS): print "
                   "class, score and box of each detection and write <stem>_detections.jpg")
        ->expected(1, -1);
    app.add_option("--out", out_dir,
                   "with --image: folder for the pictures with the boxes drawn ('' writes none)")
        ->capture_default_str();
    app.footer(df::config::options_help(df::config::DetectorServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::DetectorServiceConfig config;
    // On the command line only warnings and errors go to stderr (not the effective configuration).
    if (!images.empty() && df::log::level() == df::log::Level::kInfo) {
        df::log::set_level(df::log::Level::kWarn);
    }
    if (!df::service::load_config(flags, &config)) return 2;
    if (!images.empty() && config.model() == "simulated") {
        df::log::error(
            "--image needs a YOLO model (model: yolov5, darknet or onnx); the simulated detector "
            "reads a generated sequence's ground truth, not pictures");
        return 2;
    }
    auto source = df::boxes::open_source(config);
    if (!source) {
        df::log::error(source.status().message());
        return 2;
    }
    if (!images.empty()) return detect_images(**source, images, out_dir);
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::detector_service::DetectorNode::create(config, std::move(*source), p);
    });
}
