// tap bridge: the pipeline's topics as Foxglove views served live over the Foxglove WebSocket
// protocol (foxglove.websocket.v1), so that Foxglove Studio connects to ws://HOST:PORT.
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "core/log.hpp"
#include "dds/endpoint.hpp"
#include "dds/msg_types.hpp"
#include "foxglove/messages.hpp"
#include "foxglove_feed.hpp"
#include "foxglove_ws/websocket_server.hpp"

namespace df::tap {
namespace {

/// The topics the views are made from, by name under the namespace.
constexpr std::array<std::pair<const char*, const char*>, 6> kInputs = {{
    {dds::topics::kFrames, "df::msg::RgbdFrame"},
    {dds::topics::kDetections, "df::msg::Detections"},
    {dds::topics::kObjectSegments, "df::msg::ObjectSegments"},
    {dds::topics::kCameraPose, "df::msg::CameraPose"},
    {dds::topics::kObjectPoses, "df::msg::ObjectPoses"},
    {dds::topics::kMapCloud, "df::msg::MapCloud"},
}};

Result<std::vector<Subscription>> subscribe_inputs(const dds::Participant& p,
                                                   const BridgeOptions& b) {
    std::vector<Subscription> subs;
    for (const auto& [name, type_name] : kInputs) {
        const dds::TypeInfo* type = dds::find_type(type_name);
        if (type == nullptr)
            return error(StatusCode::kInternal, std::string("no type ") + type_name);
        const std::string topic = dds::topic_name(b.ns, name);
        // Best effort, keep the last few: a bridge that falls behind loses old samples and
        // never slows a writer. Images and maps keep `depth`; the small samples (boxes, poses)
        // keep 16, so that a burst of frames to convert does not push them out.
        const bool big = type->descriptor == &df_msg_RgbdFrame_desc ||
                         type->descriptor == &df_msg_ObjectSegments_desc ||
                         type->descriptor == &df_msg_MapCloud_desc;
        auto reader =
            dds::create_reader(p, type->descriptor, topic,
                               dds::EndpointOptions{dds::QosProfile::kTap, big ? b.depth : 16});
        if (!reader) return reader.status();
        subs.push_back(Subscription{topic, type, std::move(*reader)});
    }
    return subs;
}

}  // namespace

int cmd_bridge(const dds::Participant& p, const BridgeOptions& b, const CommonOptions& o) {
    foxglove::ServerOptions so;
    so.address = b.address;
    so.port = static_cast<uint16_t>(b.port);
    so.max_queued_bytes_per_client = static_cast<size_t>(b.max_queue_mb * 1024 * 1024);
    auto server = foxglove::WebSocketServer::start(so);
    if (!server) {
        log::error("bridge: ", server.status().message());
        return 1;
    }
    const std::string prefix = b.ns.empty() ? "foxglove" : b.ns + "/foxglove";
    std::array<uint32_t, foxglove::kChannelCount> ids{};
    for (int c = 0; c < foxglove::kChannelCount; ++c) {
        const auto channel = static_cast<foxglove::Channel>(c);
        if (channel == foxglove::Channel::kDepth && !b.scene.depth) continue;
        const foxglove::ChannelSpec spec = foxglove::channel_spec(channel, prefix, b.scene);
        ids[static_cast<size_t>(c)] = (*server)->add_channel(
            {spec.topic, "cdr", spec.schema, "omgidl", foxglove::idl_text()});
    }
    auto subs = subscribe_inputs(p, b);
    if (!subs) {
        log::error("bridge: ", subs.status().message());
        return 1;
    }
    std::printf(
        "bridge: ws://%s:%u (foxglove.websocket.v1) serving %s/... from %s/{frames,"
        "detections,object_segments,camera_pose,object_poses,map_cloud}\n",
        b.address.c_str(), static_cast<unsigned>((*server)->port()), prefix.c_str(), b.ns.c_str());
    std::fflush(stdout);

    foxglove::SceneEncoder encoder(b.scene);
    auto last_map = std::chrono::steady_clock::time_point{};
    const auto wanted = [&](foxglove::Channel c) {
        const uint32_t id = ids[static_cast<size_t>(c)];
        return id != 0 && (*server)->has_subscribers(id);
    };
    uint64_t last_sent = 0, last_dropped = 0;
    const Status s = run_loop(
        p, *subs, o.limits,
        [&](size_t i, const void* sample, const dds_sample_info_t& info) {
            if (!info.valid_data) return;
            const dds::TypeInfo& type = *(*subs)[i].type;
            for (int c = 0; c < foxglove::kChannelCount; ++c) {
                const auto channel = static_cast<foxglove::Channel>(c);
                encoder.set_wanted(channel, wanted(channel));
            }
            // Frames cost the most to convert: only when someone looks at an image.
            if (type.descriptor == &df_msg_RgbdFrame_desc &&
                !encoder.wanted(foxglove::Channel::kColor) &&
                !encoder.wanted(foxglove::Channel::kDepth) &&
                !encoder.wanted(foxglove::Channel::kMasks))
                return;
            if (type.descriptor == &df_msg_MapCloud_desc) {
                const auto now = std::chrono::steady_clock::now();
                if (now - last_map < std::chrono::duration<double>(b.map_period_s)) return;
                last_map = now;
            }
            for (foxglove::Message& m : foxglove_view(encoder, type, sample)) {
                const uint32_t id = ids[static_cast<size_t>(m.channel)];
                if (id == 0) continue;
                (*server)->publish(id, static_cast<uint64_t>(m.stamp_ns),
                                   std::make_shared<const std::vector<uint8_t>>(std::move(m.data)));
            }
        },
        [&] {
            const uint64_t sent = (*server)->sent_messages(),
                           dropped = (*server)->dropped_messages();
            if (sent != last_sent || dropped != last_dropped) {
                log::info("bridge: ", (*server)->client_count(), " client(s), ", sent - last_sent,
                          " messages sent, ", dropped - last_dropped,
                          " dropped in the last second");
            }
            last_sent = sent;
            last_dropped = dropped;
        });
    if (!s) {
        log::error("bridge: ", s.message());
        return 1;
    }
    return 0;
}

}  // namespace df::tap
