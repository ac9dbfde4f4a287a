// df_tap: look into the pipeline's topics (the `ros2 topic` of DetectFusion).
//   df_tap list | echo T | hz T | bw T | delay T | record -o F [T...] | play F | bridge
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "commands.hpp"
#include "core/log.hpp"
#include "discovery.hpp"
#include "service/service.hpp"

namespace df::tap {

int cmd_list(const dds::Participant& p, double wait_s) {
    const auto topics = discover(p, wait_s);
    if (topics.empty()) {
        std::printf("no topics found within %.1f s\n", wait_s);
        return 0;
    }
    for (const auto& [name, t] : topics) {
        std::printf("%s\n  type: %s\n  writers: %zu\n", name.c_str(), t.type.c_str(),
                    t.writers.size());
        for (const auto& w : t.writers)
            std::printf("    - %s on %s\n", w.process.c_str(), w.host.c_str());
        std::printf("  readers: %zu\n", t.readers.size());
        for (const auto& r : t.readers)
            std::printf("    - %s on %s\n", r.process.c_str(), r.host.c_str());
    }
    return 0;
}

}  // namespace df::tap

int main(int argc, char** argv) {
    df::log::set_component("tap");
    CLI::App app{
        "df_tap: list, echo, hz, bw, delay, record and play DetectFusion topics; bridge them to "
        "Foxglove Studio"};
    app.require_subcommand(1);
    app.fallthrough();  // --wait, --domain... may follow the subcommand
    // CLI11's NonNegativeNumber lets nan through; seconds and rates must be finite and >= 0.
    const CLI::Validator finite_non_negative(
        [](const std::string& text) -> std::string {
            const double v = std::strtod(text.c_str(), nullptr);
            return std::isfinite(v) && v >= 0 ? "" : "is " + text + ", allowed: finite and >= 0";
        },
        "FINITE >= 0");
    const CLI::Validator remap_form(
        [](const std::string& text) -> std::string {
            const auto eq = text.find('=');
            return eq != std::string::npos && eq > 0
                       ? ""
                       : "'" + text + "' is not FROM=TO (e.g. df/=replay/)";
        },
        "FROM=TO");
    df::config::DdsConfig dds;
    std::string transport = "auto";
    uint32_t domain = 0;
    app.add_option("--domain", domain, "DDS domain id")->default_val(0);
    app.add_option("--transport", transport, "auto, shm or udp")->default_val("auto");
    std::string interfaces;
    std::vector<std::string> peers;
    app.add_option("--interfaces", interfaces, "network interfaces, e.g. eth0 (default: loopback)");
    app.add_option("--peer", peers, "unicast discovery peer address (repeatable)");
    std::string security_dir, identity;
    app.add_option("--security-dir", security_dir,
                   "DDS Security folder made by deploy/security/make_certs.sh (default: off)");
    app.add_option("--identity", identity, "this tap's identity in --security-dir");
    df::tap::CommonOptions common;
    double wait_s = 5;
    app.add_option("--wait", wait_s, "seconds to wait for discovery")
        ->default_val(5)
        ->check(finite_non_negative);

    auto add_limits = [&common, &finite_non_negative](CLI::App* sub) {
        sub->add_option("--duration", common.limits.duration_s, "stop after this many seconds")
            ->check(finite_non_negative);
        sub->add_option("-n,--count", common.limits.count, "stop after this many messages");
        sub->add_option("--idle", common.limits.idle_s,
                        "stop when nothing arrived for this many seconds (after the first message)")
            ->check(finite_non_negative);
    };
    std::string topic;
    auto* list = app.add_subcommand("list", "topics with types, writers, readers and hosts");
    auto* echo = app.add_subcommand("echo", "print messages (arrays truncated)");
    int max_items = 8;
    echo->add_option("--items", max_items, "array elements to print")->default_val(8);
    auto* hz = app.add_subcommand("hz", "message rate");
    auto* bw = app.add_subcommand("bw", "bandwidth");
    auto* delay = app.add_subcommand("delay", "receive time minus capture time");
    for (auto* sub : {echo, hz, bw, delay}) {
        sub->add_option("topic", topic, "topic name, e.g. df/frames")->required();
        sub->add_option("--window", common.window, "samples in the statistics window")
            ->default_val(100);
        sub->add_option("--depth", common.depth,
                        "messages the reader keeps until it takes them (best effort, never slows "
                        "the writer: a burst longer than this loses its oldest)")
            ->default_val(16)
            ->check(CLI::Range(1, 100000));
        add_limits(sub);
    }
    delay->add_flag("--ok-only", common.ok_only,
                    "only messages whose status is FRAME_OK (a stage's answers for frames it "
                    "skipped or failed left out: for a detector, the round trip of the frames "
                    "it detected)");
    df::tap::RecordOptions rec;
    auto* record = app.add_subcommand("record", "record topics to an MCAP file");
    record->add_option("-o,--output", rec.output, "MCAP file to write")->required();
    record->add_option("topics", rec.topics, "topics (default: all DetectFusion topics)");
    record->add_option("--ack", rec.ack_stage,
                       "answer each frame as this stage (for lockstep capture)");
    record->add_option("--ns", rec.ns, "namespace of the stage_status topic for --ack")
        ->default_val("df");
    record->add_flag("--zstd", rec.zstd, "compress chunks with zstd");
    record->add_flag("--foxglove", rec.foxglove,
                     "also write Foxglove's schemas (colour, depth, boxes, masks, transforms, "
                     "scene, map) on <ns>/foxglove/... channels for Foxglove Studio");
    record
        ->add_option("--image-scale", rec.scene.image_scale,
                     "with --foxglove: scale images by this (0, 1]")
        ->check(CLI::Range(0.05, 1.0))
        ->capture_default_str();
    record
        ->add_option("--jpeg", rec.scene.jpeg_quality,
                     "with --foxglove: colour and masks as JPEG of this quality (0: raw)")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    add_limits(record);
    df::tap::PlayOptions play;
    auto* playc = app.add_subcommand(
        "play",
        "publish an MCAP recording; a message that fails its sample check is logged (file, "
        "message, field), not published, and play goes on, exiting 1 at the end");
    playc->add_option("input", play.input, "MCAP file")->required()->check(CLI::ExistingFile);
    playc->add_option("-r,--rate", play.rate, "speed factor (0 = as fast as possible)")
        ->default_val(1.0)
        ->check(finite_non_negative);
    playc->add_option("--remap", play.remaps, "rewrite topic prefixes, FROM=TO (repeatable)")
        ->check(remap_form);
    playc->add_option("--wait-readers", play.wait_readers,
                      "readers each topic must have before playing");
    playc->add_option("--start-wait", play.start_wait_s, "seconds to wait for those readers")
        ->default_val(5)
        ->check(finite_non_negative);
    df::tap::BridgeOptions bridge;
    auto* bridgec = app.add_subcommand(
        "bridge",
        "serve the pipeline live to Foxglove Studio (Foxglove WebSocket protocol): colour with "
        "boxes, masks, depth, camera and object frames, scene, map");
    bridgec->add_option("--ns", bridge.ns, "namespace of the pipeline's topics")
        ->capture_default_str();
    bridgec
        ->add_option("--address", bridge.address,
                     "listen on this address only (0.0.0.0: every interface)")
        ->capture_default_str();
    bridgec->add_option("--port", bridge.port, "TCP port (0: any free one)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
    bridgec->add_option("--image-scale", bridge.scene.image_scale, "scale images by this (0, 1]")
        ->check(CLI::Range(0.05, 1.0))
        ->capture_default_str();
    bridgec
        ->add_option("--jpeg", bridge.scene.jpeg_quality,
                     "colour and masks as JPEG of this quality (0: raw rgb8, ~27 MB/s at 30 Hz)")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    bridgec->add_flag("--depth-image", bridge.scene.depth,
                      "also serve the depth image (raw 16-bit, ~18 MB/s at 30 Hz full size)");
    bridgec
        ->add_option("--map-period", bridge.map_period_s,
                     "seconds between map clouds served (SLAM publishes one every "
                     "map_cloud_every_frames frames)")
        ->check(finite_non_negative)
        ->capture_default_str();
    bridgec
        ->add_option("--max-queue-mb", bridge.max_queue_mb,
                     "per client: messages beyond this many MB queued are dropped for it")
        ->check(CLI::Range(0.1, 1024.0))
        ->capture_default_str();
    add_limits(bridgec);
    CLI11_PARSE(app, argc, argv);

    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    common.wait_s = wait_s;
    dds.set_domain_id(domain);
    dds.set_transport(transport);
    dds.set_interfaces(interfaces);
    for (const auto& peer : peers) dds.add_peers(peer);
    dds.set_security_dir(security_dir);
    dds.set_security_identity(identity);
    auto participant = df::service::make_participant(dds);
    if (!participant) {
        df::log::error(participant.status().message());
        return 1;
    }
    const auto& p = *participant;
    if (*list) return df::tap::cmd_list(p, wait_s);
    if (*echo) return df::tap::cmd_echo(p, topic, common, max_items);
    if (*hz) return df::tap::cmd_hz(p, topic, common);
    if (*bw) return df::tap::cmd_bw(p, topic, common);
    if (*delay) return df::tap::cmd_delay(p, topic, common);
    if (*record) return df::tap::cmd_record(p, rec, common);
    if (*playc) return df::tap::cmd_play(p, play);
    if (*bridgec) return df::tap::cmd_bridge(p, bridge, common);
    return 2;
}
