// The SLAM service's per-frame results besides the camera pose: what was left out of the static
// map (invalid_mask) and the object maps' poses (object_poses).
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "slam_node.hpp"
#include "slam_system/map_snapshot.hpp"

namespace df::slam_service {

void SlamNode::publish_invalid(const df_msg_Header& header, const slam::FrameReport& report,
                               cv::Size frame_size) {
    if (!invalid_) return;
    auto loan = invalid_->loan();
    if (!loan) {
        log::warn("seq=", header.seq, " no invalid_mask sample: ", loan.status().message());
        return;
    }
    dynamics::LabelImage labels = report.invalid.labels;
    if (!labels.labels.empty() && labels.labels.size() != frame_size) {
        // At the frame's resolution, as object_segments: boxes and counts scaled alike.
        const float f = static_cast<float>(frame_size.width) / labels.labels.cols;
        cv::resize(labels.labels, labels.labels, frame_size, 0, 0, cv::INTER_NEAREST);
        for (dynamics::InstanceInfo& i : labels.instances) {
            i.box = cv::Rect2f(i.box.x * f, i.box.y * f, i.box.width * f, i.box.height * f);
            i.pixels = static_cast<int>(static_cast<float>(i.pixels) * f * f);
        }
    }
    const size_t dropped = dds::fill_object_segments(labels, header, loan->get());
    if (dropped > 0)
        log::warn("seq=", header.seq, " invalid_mask: ", dropped, " regions past MAX_INSTANCES");
    (*loan)->header.status = df_msg_FRAME_OK;
    if (Status s = invalid_->write(std::move(*loan)); !s)
        log::warn("seq=", header.seq, " ", s.message());
}

void SlamNode::publish_objects(const df_msg_Header& header, const slam::FrameReport& report) {
    df_msg_ObjectPoses m{};
    m.header = header;
    for (const objects::ObjectReport& r : report.objects) {
        if (m.count >= df_msg_MAX_OBJECTS) break;
        df_msg_ObjectPose& o = m.objects[m.count++];
        o.object_id = static_cast<uint32_t>(r.id);
        o.class_id = r.class_id;
        o.kind = df_msg_OBJECT_RIGID;
        o.world_T_object = dds::to_pose_msg(r.world_T_object);
        o.visible = r.pixels > 0;
        o.tracked = r.tracked;
        o.surfel_count = static_cast<uint32_t>(r.surfels);
    }
    if (Status s = object_poses_.write_copy(m); !s)
        log::warn("seq=", header.seq, " object_poses: ", s.message());
}

void SlamNode::publish_map_cloud(const df_msg_Header& header) {
    if (!map_cloud_ || !system_) return;
    const auto every = static_cast<uint64_t>(config_.map_cloud_every_frames());
    if (frames_since_map_cloud_++ % every != 0) return;
    const slam::MapSnapshot snapshot = slam::map_snapshot(
        *system_, std::min<size_t>(df_msg_MAX_MAP_POINTS,
                                   static_cast<size_t>(config_.map_cloud_max_points())));
    auto loan = map_cloud_->loan();
    if (!loan) {
        log::warn("seq=", header.seq, " no map_cloud sample: ", loan.status().message());
        return;
    }
    df_msg_MapCloud& m = *loan->get();
    // A loan holds what its chunk held before: zero it, so that the points past point_count
    // are not stale values (a recording would carry them).
    std::memset(&m, 0, sizeof(m));
    m.header = header;
    m.header.status = df_msg_FRAME_OK;
    m.surfel_count = static_cast<uint32_t>(snapshot.surfels);
    m.point_count = 0;
    for (const slam::SnapshotPoint& p : snapshot.points) {
        if (m.point_count >= df_msg_MAX_MAP_POINTS) break;
        m.points[m.point_count++] = df_msg_MapPoint{p.position_world.x(),
                                                    p.position_world.y(),
                                                    p.position_world.z(),
                                                    p.r,
                                                    p.g,
                                                    p.b,
                                                    static_cast<uint8_t>(p.object_id > 0 ? 1 : 0)};
    }
    m.object_count = 0;
    for (const slam::ObjectExtent& e : snapshot.objects) {
        if (m.object_count >= df_msg_MAX_OBJECTS) break;
        m.objects[m.object_count++] = df_msg_ObjectExtent{static_cast<uint32_t>(e.id),
                                                          e.class_id,
                                                          e.min.x(),
                                                          e.min.y(),
                                                          e.min.z(),
                                                          e.max.x(),
                                                          e.max.y(),
                                                          e.max.z()};
    }
    if (Status s = map_cloud_->write(std::move(*loan)); !s)
        log::warn("seq=", header.seq, " map_cloud: ", s.message());
}

}  // namespace df::slam_service
