// df_slam: dense surfel SLAM (static scenes). Subcommands:
//   offline FOLDER -o OUT   the whole system over a TUM-format folder in one process
//   run                     the SLAM service: <ns>/frames in, <ns>/camera_pose, stage_status out
//   params                  every parameter with its default and unit
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>

#include "config/validate.hpp"
#include "core/log.hpp"
#include "offline.hpp"
#include "service/service.hpp"
#include "slam_node.hpp"
#include "slam_system/parameters.hpp"
#include "slam_system/slam_params.hpp"

namespace {

std::atomic<bool> g_save_request{false};

void on_sigusr1(int) { g_save_request.store(true); }

int run_service(const df::config::SlamServiceConfig& config) {
    df::slam::SystemConfig system_config;
    if (auto s = df::slam::apply(config.slam(), &system_config); !s) {
        df::log::error(s.message());
        return 2;
    }
    df::log::info("SLAM parameters:\n", df::slam::describe(system_config));
    if (std::string e = df::slam::validate(system_config); !e.empty()) {
        df::log::error("SLAM configuration: ", e);
        return 2;
    }
    struct sigaction action {};
    action.sa_handler = on_sigusr1;
    sigemptyset(&action.sa_mask);
    sigaction(SIGUSR1, &action, nullptr);
    auto participant = df::service::make_participant(config.dds());
    if (!participant) {
        df::log::error(participant.status().message());
        return 1;
    }
    auto node =
        df::slam_service::SlamNode::create(config, system_config, *participant, &g_save_request);
    if (!node) {
        df::log::error(node.status().message());
        return 1;
    }
    if (auto s = (*node)->run(); !s) {
        df::log::error(s.message());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("slam");
    CLI::App app{
        "df_slam: dense surfel SLAM over RGB-D frames (offline over a folder, or as the "
        "pipeline's SLAM service)"};
    app.require_subcommand(1);
    df::service::ConfigFlags flags;

    CLI::App* offline = app.add_subcommand("offline",
                                           "run over a TUM-format folder, write "
                                           "trajectory, map, timings, print ATE");
    df::slam_service::OfflineOptions options;
    offline->add_option("folder", options.folder, "TUM RGB-D folder (or df_make_sequence output)")
        ->required();
    offline->add_option("-o,--out", options.out_dir, "output folder")->required();
    offline->add_option("--preset", options.preset,
                        "camera: fr1, fr2, fr3, 7scenes (default: the folder's intrinsics.txt, "
                        "else fr3)");
    offline->add_option("--max-frames", options.max_frames, "stop after this many frames");
    offline->add_option("--masks", options.masks,
                        "ground-truth masks: a folder of per-frame <stamp>.png (non-zero = leave "
                        "out of tracking and fusion), e.g. a generated sequence's instances/; "
                        "replaces segmentation, detection and motion segmentation");
    offline
        ->add_option("--mask-dilate", options.mask_dilate_px, "grow the masks by this many pixels")
        ->check(CLI::Range(0, 32));
    offline
        ->add_option("--dynamics", options.dynamics,
                     "on: the whole system (segmentation, detection, motion segmentation, "
                     "two-stage tracking); off: the static core alone (for comparisons)")
        ->check(CLI::IsMember({"on", "off"}));
    offline
        ->add_option("--detector", options.detector,
                     "yolov5 (the detector's configuration: detector { ... }), simulated "
                     "(SIMULATED: boxes from a generated sequence's ground truth), or none "
                     "(motion segmentation alone)")
        ->check(CLI::IsMember({"yolov5", "simulated", "none"}));
    offline
        ->add_option("--detect-every", options.detect_every,
                     "run the detector on every Nth frame only (as a detector slower than the "
                     "camera would); the frames between reuse its boxes, and SLAM carries the "
                     "last instances forward over them (propagation { }; default 1: every frame)")
        ->check(CLI::Range(1, 1000));
    offline->add_option("--write-masks", options.write_masks,
                        "write invalid/, motion/, segments/ and object_masks/ label PNGs per frame (default true)");
    offline->add_flag("--overlay", options.overlay,
                      "also write overlay/<stamp>.png: the colour image with what was left out "
                      "tinted, boxes and class names drawn");
    offline->add_option("--foxglove", options.foxglove,
                        "also write the run as Foxglove views to this MCAP file (colour with "
                        "boxes, masks, depth, camera and object frames, scene, map every "
                        "map_cloud_every_frames frames): docs/viewing.md");
    offline->add_option("--groundtruth", options.groundtruth,
                        "ground truth for the ATE (default: <folder>/groundtruth.txt)");

    CLI::App* run = app.add_subcommand("run", "the SLAM service (DDS)");
    // --config/--set belong to the program; given after a subcommand they fall through to it.
    df::service::add_config_flags(app, &flags);
    offline->fallthrough();
    run->fallthrough();

    CLI::App* params = app.add_subcommand("params", "print every SLAM parameter, default, unit");
    CLI11_PARSE(app, argc, argv);

    if (params->parsed()) {
        std::fputs(df::slam::params_table(df::slam::SystemConfig{}).c_str(), stdout);
        std::printf("\n# the service's own options (df_slam run / offline):\n%s",
                    df::config::options_help(df::config::SlamServiceConfig::descriptor()).c_str());
        return 0;
    }
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::SlamServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    if (offline->parsed()) return df::slam_service::run_offline(options, config);
    return run_service(config);
}
