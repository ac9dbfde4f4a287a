#include "print.hpp"

#include <cstring>
#include <sstream>

namespace df::tap {
namespace {

const char* status_name(df_msg_FrameStatus s) {
    switch (s) {
        case df_msg_FRAME_OK:
            return "OK";
        case df_msg_FRAME_SKIPPED:
            return "SKIPPED";
        case df_msg_FRAME_FAILED:
            return "FAILED";
    }
    return "?";
}

const char* kind_name(df_msg_ObjectKind k) {
    switch (k) {
        case df_msg_OBJECT_RIGID:
            return "RIGID";
        case df_msg_OBJECT_NON_RIGID:
            return "NON_RIGID";
        case df_msg_OBJECT_UNKNOWN:
            return "UNKNOWN";
    }
    return "?";
}

void header(std::ostringstream& o, const df_msg_Header& h) {
    o << "header:\n  capture_ns: " << h.capture_ns << "\n  sensor_ns: " << h.sensor_ns
      << "\n  seq: " << h.seq << "\n  epoch: " << h.epoch << "\n  source_id: " << h.source_id
      << "\n  status: " << status_name(h.status) << "\n";
}

template <typename T>
void array(std::ostringstream& o, const char* name, const T* data, size_t n, int max_items) {
    o << name << ": [";
    const size_t shown = n < static_cast<size_t>(max_items) ? n : static_cast<size_t>(max_items);
    for (size_t i = 0; i < shown; ++i) o << (i ? ", " : "") << +data[i];
    if (n > shown) o << ", ... (" << n << " in all)";
    o << "]\n";
}

void pose(std::ostringstream& o, const char* indent, const df_msg_Pose& p) {
    o << indent << "t: [" << p.tx << ", " << p.ty << ", " << p.tz << "]\n"
      << indent << "q: [" << p.qx << ", " << p.qy << ", " << p.qz << ", " << p.qw << "]\n";
}

void frame(std::ostringstream& o, const df_msg_RgbdFrame& f, int max_items) {
    header(o, f.header);
    const size_t px = static_cast<size_t>(f.width) * f.height;
    size_t valid = 0;
    for (size_t i = 0; i < px && i < df_msg_MAX_PIXELS; ++i) valid += f.depth[i] != 0;
    o << "width: " << f.width << "\nheight: " << f.height
      << "\nintrinsics: {fx: " << f.intrinsics.fx << ", fy: " << f.intrinsics.fy
      << ", cx: " << f.intrinsics.cx << ", cy: " << f.intrinsics.cy
      << "}\ndepth_units_per_m: " << f.depth_units_per_m << "\n";
    array(o, "rgb", f.rgb, px * 3 < df_msg_MAX_RGB_BYTES ? px * 3 : df_msg_MAX_RGB_BYTES,
          max_items);
    array(o, "depth", f.depth, px < df_msg_MAX_PIXELS ? px : df_msg_MAX_PIXELS, max_items);
    o << "depth_valid_pixels: " << valid << "\n";
}

void segments(std::ostringstream& o, const df_msg_ObjectSegments& s, int max_items) {
    header(o, s.header);
    o << "width: " << s.width << "\nheight: " << s.height
      << "\ndetections_used: " << (s.detections_used ? "true" : "false")
      << "\ndetections_seq: " << s.detections_seq << "\ninstance_count: " << s.instance_count
      << "\ninstances:\n";
    for (uint32_t i = 0; i < s.instance_count && i < df_msg_MAX_INSTANCES; ++i) {
        const auto& in = s.instances[i];
        o << "  - {id: " << in.instance_id << ", class_id: " << in.class_id
          << ", score: " << in.score << ", kind: " << kind_name(in.kind) << ", box: [" << in.box_x
          << ", " << in.box_y << ", " << in.box_w << ", " << in.box_h
          << "], pixels: " << in.pixel_count << ", age: " << in.age_frames << "}\n";
    }
    array(o, "labels", s.labels, static_cast<size_t>(s.width) * s.height, max_items);
}

}  // namespace

std::string print_sample(const dds::TypeInfo& type, const void* sample, int max_items) {
    std::ostringstream o;
    const std::string name = type.name;
    if (name == "df::msg::RgbdFrame") {
        frame(o, *static_cast<const df_msg_RgbdFrame*>(sample), max_items);
    } else if (name == "df::msg::CompressedImage") {
        const auto& c = *static_cast<const df_msg_CompressedImage*>(sample);
        header(o, c.header);
        o << "width: " << c.width << "\nheight: " << c.height
          << "\nsource_width: " << c.source_width << "\nsource_height: " << c.source_height
          << "\nformat: " << std::string(c.format, strnlen(c.format, 8)) << "\n";
        array(o, "data", c.data._buffer, c.data._length, max_items);
    } else if (name == "df::msg::Detections") {
        const auto& d = *static_cast<const df_msg_Detections*>(sample);
        header(o, d.header);
        o << "image: [" << d.image_width << ", " << d.image_height << "]\ncount: " << d.count
          << "\nboxes:\n";
        for (uint32_t i = 0; i < d.count && i < df_msg_MAX_DETECTIONS; ++i) {
            const auto& b = d.boxes[i];
            o << "  - {class_id: " << b.class_id << ", score: " << b.score << ", box: [" << b.x
              << ", " << b.y << ", " << b.w << ", " << b.h << "]}\n";
        }
    } else if (name == "df::msg::GeometricSegments") {
        const auto& g = *static_cast<const df_msg_GeometricSegments*>(sample);
        header(o, g.header);
        o << "width: " << g.width << "\nheight: " << g.height
          << "\nsegment_count: " << g.segment_count << "\n";
        array(o, "labels", g.labels, static_cast<size_t>(g.width) * g.height, max_items);
    } else if (name == "df::msg::ObjectSegments") {
        segments(o, *static_cast<const df_msg_ObjectSegments*>(sample), max_items);
    } else if (name == "df::msg::CameraPose") {
        const auto& p = *static_cast<const df_msg_CameraPose*>(sample);
        header(o, p.header);
        o << "world_T_camera:\n";
        pose(o, "  ", p.world_T_camera);
        o << "state: "
          << (p.state == df_msg_TRACKING_OK     ? "OK"
              : p.state == df_msg_TRACKING_LOST ? "LOST"
                                                : "INITIALIZING")
          << "\ninlier_ratio: " << p.inlier_ratio << "\nresidual: " << p.residual << "\n";
    } else if (name == "df::msg::ObjectPoses") {
        const auto& p = *static_cast<const df_msg_ObjectPoses*>(sample);
        header(o, p.header);
        o << "count: " << p.count << "\nobjects:\n";
        for (uint32_t i = 0; i < p.count && i < df_msg_MAX_OBJECTS; ++i) {
            const auto& ob = p.objects[i];
            o << "  - object_id: " << ob.object_id << "\n    class_id: " << ob.class_id
              << "\n    kind: " << kind_name(ob.kind)
              << "\n    visible: " << (ob.visible ? "true" : "false")
              << "\n    tracked: " << (ob.tracked ? "true" : "false")
              << "\n    surfels: " << ob.surfel_count << "\n    world_T_object:\n";
            pose(o, "      ", ob.world_T_object);
        }
    } else if (name == "df::msg::MapCloud") {
        const auto& m = *static_cast<const df_msg_MapCloud*>(sample);
        header(o, m.header);
        o << "surfel_count: " << m.surfel_count << "\npoint_count: " << m.point_count
          << "\npoints:\n";
        for (uint32_t i = 0;
             i < m.point_count && i < df_msg_MAX_MAP_POINTS && i < static_cast<uint32_t>(max_items);
             ++i) {
            const auto& p = m.points[i];
            o << "  - [" << p.x << ", " << p.y << ", " << p.z << "] rgb " << int(p.r) << " "
              << int(p.g) << " " << int(p.b) << (p.source ? " object" : "") << "\n";
        }
        o << "object_count: " << m.object_count << "\nobjects:\n";
        for (uint32_t i = 0; i < m.object_count && i < df_msg_MAX_OBJECTS; ++i) {
            const auto& e = m.objects[i];
            o << "  - object_id: " << e.object_id << "\n    class_id: " << e.class_id
              << "\n    min: [" << e.min_x << ", " << e.min_y << ", " << e.min_z << "]"
              << "\n    max: [" << e.max_x << ", " << e.max_y << ", " << e.max_z << "]\n";
        }
    } else if (name == "df::msg::StageStatus") {
        const auto& s = *static_cast<const df_msg_StageStatus*>(sample);
        header(o, s.header);
        o << "stage: " << dds::get_name(s.stage) << "\ntimings_ms:\n";
        for (uint32_t i = 0; i < s.timing_count && i < df_msg_MAX_STAGE_TIMINGS; ++i) {
            o << "  " << dds::get_name(s.timings[i].name) << ": " << s.timings[i].ms << "\n";
        }
    } else {
        o << "(no printer for type " << name << ")\n";
    }
    return o.str();
}

}  // namespace df::tap
