#include "foxglove_feed.hpp"

#include "dds/msg_convert.hpp"
#include "dds/sample_check.hpp"
#include "df_msgs.h"
#include "draw/pictures.hpp"

namespace df::tap {
namespace {

Eigen::Isometry3d isometry(const df_msg_Pose& p) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized().toRotationMatrix();
    t.translation() = Eigen::Vector3d(p.tx, p.ty, p.tz);
    return t;
}

int64_t stamp(const df_msg_Header& h) { return static_cast<int64_t>(h.capture_ns); }

std::vector<foxglove::Message> frames(foxglove::SceneEncoder& e, const df_msg_RgbdFrame& m) {
    auto c = dds::checked(m);
    if (!c || m.header.status != df_msg_FRAME_OK) return {};
    // Views of the sample's memory: the encoder copies what it keeps.
    io::RgbdImage image;
    image.rgb = dds::rgb_view(*c);
    image.depth = dds::depth_view(*c);
    return e.frame(m.header.seq, stamp(m.header), image);
}

std::vector<foxglove::Message> detections(foxglove::SceneEncoder& e, const df_msg_Detections& m) {
    if (!dds::checked(m) || m.header.status != df_msg_FRAME_OK) return {};
    std::vector<detect::Detection> boxes;
    for (uint32_t i = 0; i < m.count; ++i) {
        const df_msg_Detection& b = m.boxes[i];
        boxes.push_back(
            {cv::Rect2f(b.x, b.y, b.w, b.h), b.class_id, draw::class_name(b.class_id), b.score});
    }
    return e.detections(stamp(m.header), boxes, m.image_width);
}

std::vector<foxglove::Message> segments(foxglove::SceneEncoder& e, const df_msg_ObjectSegments& m) {
    auto c = dds::checked(m);
    if (!c || m.header.status != df_msg_FRAME_OK) return {};
    return e.instances(m.header.seq, stamp(m.header), dds::to_label_image(*c));
}

std::vector<foxglove::Message> camera(foxglove::SceneEncoder& e, const df_msg_CameraPose& m) {
    if (!dds::checked(m) || m.header.status != df_msg_FRAME_OK || m.state != df_msg_TRACKING_OK)
        return {};
    return e.camera_pose(stamp(m.header), isometry(m.world_T_camera));
}

std::vector<foxglove::Message> objects(foxglove::SceneEncoder& e, const df_msg_ObjectPoses& m) {
    if (!dds::checked(m)) return {};
    std::vector<foxglove::ObjectState> states;
    for (uint32_t i = 0; i < m.count; ++i) {
        const df_msg_ObjectPose& o = m.objects[i];
        states.push_back({o.object_id, o.class_id, isometry(o.world_T_object), o.tracked});
    }
    return e.object_poses(stamp(m.header), states);
}

std::vector<foxglove::Message> map(foxglove::SceneEncoder& e, const df_msg_MapCloud& m) {
    if (!dds::checked(m) || m.header.status != df_msg_FRAME_OK) return {};
    std::vector<foxglove::CloudPoint> points(m.point_count);
    for (uint32_t i = 0; i < m.point_count; ++i) {
        const df_msg_MapPoint& p = m.points[i];
        points[i] = {p.x, p.y, p.z, p.r, p.g, p.b, 255};
    }
    std::vector<foxglove::ObjectBounds> bounds;
    for (uint32_t i = 0; i < m.object_count; ++i) {
        const df_msg_ObjectExtent& x = m.objects[i];
        bounds.push_back({x.object_id, x.class_id, Eigen::Vector3f(x.min_x, x.min_y, x.min_z),
                          Eigen::Vector3f(x.max_x, x.max_y, x.max_z)});
    }
    return e.map(stamp(m.header), points, bounds);
}

}  // namespace

bool has_foxglove_view(const dds::TypeInfo& t) {
    return t.descriptor == &df_msg_RgbdFrame_desc || t.descriptor == &df_msg_Detections_desc ||
           t.descriptor == &df_msg_ObjectSegments_desc || t.descriptor == &df_msg_CameraPose_desc ||
           t.descriptor == &df_msg_ObjectPoses_desc || t.descriptor == &df_msg_MapCloud_desc;
}

std::vector<foxglove::Message> foxglove_view(foxglove::SceneEncoder& e, const dds::TypeInfo& t,
                                             const void* sample) {
    if (t.descriptor == &df_msg_RgbdFrame_desc)
        return frames(e, *static_cast<const df_msg_RgbdFrame*>(sample));
    if (t.descriptor == &df_msg_Detections_desc)
        return detections(e, *static_cast<const df_msg_Detections*>(sample));
    if (t.descriptor == &df_msg_ObjectSegments_desc)
        return segments(e, *static_cast<const df_msg_ObjectSegments*>(sample));
    if (t.descriptor == &df_msg_CameraPose_desc)
        return camera(e, *static_cast<const df_msg_CameraPose*>(sample));
    if (t.descriptor == &df_msg_ObjectPoses_desc)
        return objects(e, *static_cast<const df_msg_ObjectPoses*>(sample));
    if (t.descriptor == &df_msg_MapCloud_desc)
        return map(e, *static_cast<const df_msg_MapCloud*>(sample));
    return {};
}

std::string topic_ns(const std::string& topic) {
    const size_t slash = topic.find('/');
    return slash == std::string::npos ? std::string() : topic.substr(0, slash);
}

}  // namespace df::tap
