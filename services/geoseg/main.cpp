// df_geoseg: the geometric segmentation service. Subscribes to <ns>/frames, publishes
// <ns>/geometric_segments and <ns>/stage_status for every frame (docs/segmentation.md).
#include <CLI/CLI.hpp>

#include "config/validate.hpp"
#include "core/log.hpp"
#include "geoseg_node.hpp"
#include "service/service.hpp"

int main(int argc, char** argv) {
    df::log::set_component("geoseg");
    CLI::App app{
        "df_geoseg: geometric segmentation of depth frames (Tateno et al. 2015) as a "
        "DDS service"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    app.footer(df::config::options_help(df::config::GeosegServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::GeosegServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    df::seg::GeometricSegmentationConfig seg;
    df::slam::PreprocessConfig preprocess;
    if (auto s = df::geoseg_service::apply(config.params(), &seg, &preprocess); !s) {
        df::log::error(s.message());
        return 2;
    }
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::geoseg_service::GeosegNode::create(config, seg, preprocess, p);
    });
}
