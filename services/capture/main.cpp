// df_capture: publishes RGB-D frames from a TUM folder or an OpenNI2 camera on <ns>/frames.
#include <CLI/CLI.hpp>

#include "capture_node.hpp"
#include "config/validate.hpp"
#include "core/log.hpp"
#include "service/service.hpp"

int main(int argc, char** argv) {
    df::log::set_component("capture");
    CLI::App app{"df_capture: RGB-D frames from a TUM folder or an OpenNI2 camera onto DDS"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    app.footer(df::config::options_help(df::config::CaptureConfig::descriptor()));
    std::string folder;
    app.add_option("folder", folder, "TUM RGB-D folder (shortcut for --set 'folder: \"...\"')");
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();

    df::config::CaptureConfig config;
    if (!folder.empty())
        flags.overrides.insert(flags.overrides.begin(), "folder: \"" + folder + "\"");
    if (!df::service::load_config(flags, &config)) return 2;

    auto source = df::capture::open_source(config);
    if (!source) {
        df::log::error("cannot open the input: ", source.status().message());
        return 1;
    }
    auto participant = df::service::make_participant(config.dds());
    if (!participant) {
        df::log::error(participant.status().message());
        return 1;
    }
    auto node = df::capture::CaptureNode::create(config, *participant, std::move(*source));
    if (!node) {
        df::log::error(node.status().message());
        return 1;
    }
    auto stats = (*node)->run();
    if (!stats) {
        df::log::error(stats.status().message());
        return 1;
    }
    df::log::info("done: ", stats->published, " frames published, ", stats->bad_frames,
                  " bad frames skipped, ", stats->lockstep_timeouts, " lockstep timeouts, ",
                  stats->stages_left, " frames published while a lockstep stage was gone, ",
                  stats->frames_abandoned, " waits ended by a frames reader leaving, ",
                  stats->bad_answers, " stage_status samples refused, ", stats->loan_fallbacks,
                  " loan fallbacks, ",
                  stats->elapsed_s > 0 ? stats->published / stats->elapsed_s : 0.0, " frames/s");
    return 0;
}
