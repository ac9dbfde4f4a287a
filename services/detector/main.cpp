// df_detector: 2D object detection on every frame (YOLO through OpenCV, or the SIMULATED
// detector on a generated sequence), as a DDS service (docs/segmentation.md).
#include <CLI/CLI.hpp>

#include "config/validate.hpp"
#include "core/log.hpp"
#include "detector_node.hpp"
#include "service/service.hpp"

int main(int argc, char** argv) {
    df::log::set_component("detector");
    CLI::App app{
        "df_detector: COCO object detection (YOLO, or simulated from ground truth) as a "
        "DDS service"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    app.footer(df::config::options_help(df::config::DetectorServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::DetectorServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    auto source = df::boxes::open_source(config);
    if (!source) {
        df::log::error(source.status().message());
        return 2;
    }
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::detector_service::DetectorNode::create(config, std::move(*source), p);
    });
}
