#pragma once
/// The tap subcommands. Each returns a process exit code (0 ok, 1 runtime error, 2 bad usage).
#include <string>
#include <vector>

#include "dds/participant.hpp"
#include "foxglove/scene.hpp"
#include "subscription.hpp"

namespace df::tap {

struct CommonOptions {
    double wait_s = 5;  ///< how long to wait for a topic's writer to be discovered
    RunLimits limits;
    int window = 100;      ///< samples in the statistics window (hz, bw, delay)
    int depth = 16;        ///< reader history: samples kept until taken (a burst beyond it drops)
    bool ok_only = false;  ///< delay: only samples whose header status is FRAME_OK
};

int cmd_list(const dds::Participant& p, double wait_s);
int cmd_echo(const dds::Participant& p, const std::string& topic, const CommonOptions& o,
             int max_items);
int cmd_hz(const dds::Participant& p, const std::string& topic, const CommonOptions& o);
int cmd_bw(const dds::Participant& p, const std::string& topic, const CommonOptions& o);
int cmd_delay(const dds::Participant& p, const std::string& topic, const CommonOptions& o);

struct RecordOptions {
    std::string output;
    std::vector<std::string> topics;  ///< empty: every DetectFusion topic discovered
    std::string ack_stage;  ///< answer each frame on <ns>/stage_status as this stage (lockstep)
    std::string ns = "df";
    bool zstd = false;
    /// Also write Foxglove's own schemas (images, boxes, masks, transforms, map) on
    /// "<ns>/foxglove/..." channels, for Foxglove Studio.
    bool foxglove = false;
    foxglove::SceneOptions scene;
};
int cmd_record(const dds::Participant& p, const RecordOptions& r, const CommonOptions& o);

struct PlayOptions {
    std::string input;
    double rate = 1.0;                ///< 0 = as fast as possible
    std::vector<std::string> remaps;  ///< "from=to" topic prefix rewrites
    double start_wait_s = 2;          ///< wait for readers before playing
    uint32_t wait_readers = 0;        ///< readers each topic must have before playing
};
int cmd_play(const dds::Participant& p, const PlayOptions& play);

/// `bridge`: the Foxglove views of namespace `ns` served over the Foxglove WebSocket protocol.
struct BridgeOptions {
    std::string ns = "df";
    std::string address = "127.0.0.1";  ///< listen only here (0.0.0.0: every interface)
    int port = 8765;
    /// Images as JPEG of quality 80 at full size, no depth image: about 1.5 MB/s at 30 Hz.
    foxglove::SceneOptions scene = [] {
        foxglove::SceneOptions s;
        s.jpeg_quality = 80;
        s.depth = false;
        return s;
    }();
    double map_period_s = 1.0;  ///< at most one map cloud per this many seconds
    double max_queue_mb = 8;    ///< per client; beyond it new messages to it are dropped
    int depth = 2;  ///< frames, segments, maps kept for the bridge (oldest dropped); others 16
};
int cmd_bridge(const dds::Participant& p, const BridgeOptions& bridge, const CommonOptions& o);

}  // namespace df::tap
