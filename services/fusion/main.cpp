// df_fusion: joins geometric segments and detections by frame, publishes object segments for
// every frame (docs/segmentation.md).
#include <CLI/CLI.hpp>

#include "config/validate.hpp"
#include "core/log.hpp"
#include "fusion_node.hpp"
#include "service/service.hpp"

int main(int argc, char** argv) {
    df::log::set_component("fusion");
    CLI::App app{
        "df_fusion: instance segmentation from detector boxes and geometric segments, "
        "joined by frame with a detection deadline"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    app.footer(df::config::options_help(df::config::FusionServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::FusionServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    auto settings = df::fusion_service::settings_from(config);
    if (!settings) {
        df::log::error("configuration: ", settings.status().message());
        return 2;
    }
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::fusion_service::FusionNode::create(config, *settings, p);
    });
}
