#include "foxglove_output.hpp"

#include "draw/pictures.hpp"
#include "foxglove/messages.hpp"
#include "slam_system/map_snapshot.hpp"

namespace df::slam_service {

Result<FoxgloveOutput> FoxgloveOutput::open(const std::string& path, int map_every) {
    // zstd chunks and JPEG images: about 0.3 MB a frame instead of 2.5 (raw colour, depth and
    // masks).
    mcap::WriterOptions wo;
    wo.compression = mcap::WriterOptions::Compression::kZstd;
    auto writer = mcap::Writer::open(path, wo);
    if (!writer) return writer.status();
    foxglove::SceneOptions options;
    options.jpeg_quality = 90;
    FoxgloveOutput out(std::move(*writer), map_every, options);
    for (int c = 0; c < foxglove::kChannelCount; ++c) {
        const auto spec =
            foxglove::channel_spec(static_cast<foxglove::Channel>(c), "df/foxglove", options);
        auto schema = out.writer_->add_schema(spec.schema, "omgidl", foxglove::idl_text());
        if (!schema) return schema.status();
        auto channel = out.writer_->add_channel(*schema, spec.topic, "cdr");
        if (!channel) return channel.status();
        out.channels_[static_cast<size_t>(c)] = *channel;
    }
    return out;
}

FoxgloveOutput::FoxgloveOutput(std::unique_ptr<mcap::Writer> writer, int map_every,
                               const foxglove::SceneOptions& options)
    : writer_(std::move(writer)),
      map_every_(map_every),
      encoder_(std::make_unique<foxglove::SceneEncoder>(options)) {}

Status FoxgloveOutput::put(const std::vector<foxglove::Message>& messages, uint64_t seq) {
    for (const foxglove::Message& m : messages) {
        const auto stamp = static_cast<uint64_t>(m.stamp_ns);
        DF_RETURN_IF_ERROR(writer_->write(channels_[static_cast<size_t>(m.channel)],
                                          static_cast<uint32_t>(seq), stamp, stamp, m.data.data(),
                                          m.data.size()));
    }
    return Status::ok();
}

Status FoxgloveOutput::write(uint64_t seq, const io::RgbdImage& image,
                             const dynamics::FrameSegments& segments,
                             const slam::FrameReport& report, const slam::SlamSystem& system) {
    const int64_t stamp = image.sensor_ns;
    DF_RETURN_IF_ERROR(put(encoder_->frame(seq, stamp, image), seq));
    // The boxes the frame's instances came from (a detector's, or none for given masks).
    std::vector<detect::Detection> boxes;
    for (const dynamics::InstanceInfo& i : segments.objects.instances) {
        if (i.box.width > 0)
            boxes.push_back({i.box, i.class_id, draw::class_name(i.class_id), i.score});
    }
    DF_RETURN_IF_ERROR(put(encoder_->detections(stamp, boxes, image.rgb.cols), seq));
    DF_RETURN_IF_ERROR(put(encoder_->instances(seq, stamp, segments.objects), seq));
    std::vector<foxglove::ObjectState> objects;
    for (const objects::ObjectReport& o : report.objects) {
        objects.push_back({static_cast<uint32_t>(o.id), o.class_id, o.world_T_object, o.tracked});
    }
    DF_RETURN_IF_ERROR(put(encoder_->object_poses(stamp, objects), seq));
    if (map_every_ > 0 && seq % static_cast<uint64_t>(map_every_) == 0) {
        const slam::MapSnapshot snapshot = slam::map_snapshot(system, 65536);
        std::vector<foxglove::CloudPoint> points;
        points.reserve(snapshot.points.size());
        for (const slam::SnapshotPoint& p : snapshot.points) {
            points.push_back({p.position_world.x(), p.position_world.y(), p.position_world.z(), p.r,
                              p.g, p.b, 255});
        }
        std::vector<foxglove::ObjectBounds> bounds;
        for (const slam::ObjectExtent& e : snapshot.objects) {
            bounds.push_back({static_cast<uint32_t>(e.id), e.class_id, e.min, e.max});
        }
        DF_RETURN_IF_ERROR(put(encoder_->map(stamp, points, bounds), seq));
    }
    return put(encoder_->camera_pose(stamp, report.world_T_camera), seq);
}

Status FoxgloveOutput::close() { return writer_->close(); }

}  // namespace df::slam_service
