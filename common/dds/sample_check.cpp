#include "dds/sample_check.hpp"

#include <bitset>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "core/log.hpp"

namespace df::dds {
namespace {

// Bounds for geometry and boxes: generous, but far inside what float -> int conversions and
// pixel arithmetic survive.
constexpr double kMaxFocalPx = 100000;
constexpr double kMaxDepthUnitsPerM = 1e6;
constexpr double kMaxBoxCoordPx = 131072;
constexpr double kMaxPositionM = 1e6;
constexpr int32_t kMaxClassId = 79;  // COCO 0..79, -1 unknown (idl/df_msgs.idl)

Status bad(const char* type, const std::string& what) {
    return error(StatusCode::kInvalidArgument, std::string(type) + "." + what);
}

template <typename V>
std::string str(V v) {
    std::ostringstream s;
    s << +v;
    return s.str();
}

/// field <= limit, named as "field value > LIMIT_NAME limit".
template <typename V, typename L>
Status at_most(const char* type, const std::string& field, V value, L limit,
               const char* limit_name) {
    if (static_cast<uint64_t>(value) <= static_cast<uint64_t>(limit)) return Status::ok();
    return bad(type, field + " " + str(value) + " > " + limit_name + " " + str(limit));
}

/// value finite and in [lo, hi].
Status in_range(const char* type, const std::string& field, double value, double lo, double hi) {
    if (std::isfinite(value) && value >= lo && value <= hi) return Status::ok();
    return bad(type, field + " " + str(value) + " not in [" + str(lo) + ", " + str(hi) + "]");
}

Status positive(const char* type, const std::string& field, double value, double hi) {
    if (std::isfinite(value) && value > 0 && value <= hi) return Status::ok();
    return bad(type, field + " " + str(value) + " not in (0, " + str(hi) + "]");
}

/// An enum field's stored value. Read as bytes: a sample from the network or shared memory may
/// hold any value, and loading an out-of-range value as the enum type is undefined behaviour.
template <typename E>
int32_t enum_value(const E& field) {
    static_assert(sizeof(E) == sizeof(int32_t), "IDL enums are 32-bit");
    int32_t v = 0;
    std::memcpy(&v, &field, sizeof v);
    return v;
}

Status check_status(const char* type, const df_msg_FrameStatus& status) {
    const int32_t v = enum_value(status);
    if (v >= df_msg_FRAME_OK && v <= df_msg_FRAME_FAILED) return Status::ok();
    return bad(type, "header.status " + str(v) + " not a FrameStatus (0..2)");
}

/// A boolean field's stored byte must be 0 or 1 (any other is undefined behaviour to load).
Status check_bool(const char* type, const std::string& field, const bool& b) {
    uint8_t v = 0;
    std::memcpy(&v, &b, 1);
    if (v <= 1) return Status::ok();
    return bad(type, field + " " + str(v) + " not a boolean (0 or 1)");
}

Status check_kind(const char* type, const std::string& field, const df_msg_ObjectKind& kind) {
    const int32_t v = enum_value(kind);
    if (v >= df_msg_OBJECT_RIGID && v <= df_msg_OBJECT_UNKNOWN) return Status::ok();
    return bad(type, field + " " + str(v) + " not an ObjectKind (0..2)");
}

Status check_size(const char* type, uint16_t width, uint16_t height, bool nonzero) {
    DF_RETURN_IF_ERROR(at_most(type, "width", width, df_msg_MAX_WIDTH, "MAX_WIDTH"));
    DF_RETURN_IF_ERROR(at_most(type, "height", height, df_msg_MAX_HEIGHT, "MAX_HEIGHT"));
    if (nonzero && (width == 0 || height == 0)) {
        return bad(type, "width x height " + str(width) + "x" + str(height) + " is empty");
    }
    return Status::ok();
}

Status check_class(const char* type, const std::string& field, int32_t class_id) {
    if (class_id >= -1 && class_id <= kMaxClassId) return Status::ok();
    return bad(type, field + " " + str(class_id) + " not in [-1, " + str(kMaxClassId) + "]");
}

Status check_box(const char* type, const std::string& field, float x, float y, float w, float h) {
    DF_RETURN_IF_ERROR(in_range(type, field + ".x", x, -kMaxBoxCoordPx, kMaxBoxCoordPx));
    DF_RETURN_IF_ERROR(in_range(type, field + ".y", y, -kMaxBoxCoordPx, kMaxBoxCoordPx));
    DF_RETURN_IF_ERROR(in_range(type, field + ".w", w, 0, kMaxBoxCoordPx));
    return in_range(type, field + ".h", h, 0, kMaxBoxCoordPx);
}

Status check_pose(const char* type, const std::string& field, const df_msg_Pose& p,
                  bool unit_quaternion) {
    const double t[3] = {p.tx, p.ty, p.tz};
    const char* tn[3] = {".tx", ".ty", ".tz"};
    for (int i = 0; i < 3; ++i) {
        DF_RETURN_IF_ERROR(in_range(type, field + tn[i], t[i], -kMaxPositionM, kMaxPositionM));
    }
    const double q[4] = {p.qx, p.qy, p.qz, p.qw};
    const char* qn[4] = {".qx", ".qy", ".qz", ".qw"};
    for (int i = 0; i < 4; ++i) DF_RETURN_IF_ERROR(in_range(type, field + qn[i], q[i], -1, 1));
    if (!unit_quaternion) return Status::ok();
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::abs(norm - 1.0) <= 1e-3) return Status::ok();
    return bad(type, field + " quaternion norm " + str(norm) + " not within 1e-3 of 1");
}

/// The pixel size an encoded PNG or JPEG announces in its header, without decoding it; false
/// when the bytes do not start like that format.
bool encoded_size(const uint8_t* data, size_t n, bool png, uint32_t* width, uint32_t* height) {
    auto be16 = [&](size_t i) { return static_cast<uint32_t>(data[i] << 8 | data[i + 1]); };
    if (png) {
        static const uint8_t kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        if (n < 24 || std::memcmp(data, kSig, 8) != 0 || std::memcmp(data + 12, "IHDR", 4) != 0)
            return false;
        *width = be16(16) << 16 | be16(18);
        *height = be16(20) << 16 | be16(22);
        return true;
    }
    if (n < 4 || data[0] != 0xFF || data[1] != 0xD8) return false;
    size_t i = 2;
    while (i + 4 <= n) {
        if (data[i] != 0xFF) return false;
        const uint8_t marker = data[i + 1];
        if (marker == 0xFF) {  // fill byte
            ++i;
            continue;
        }
        const uint32_t len = be16(i + 2);
        // Start-of-frame markers C0..CF except DHT (C4), JPG (C8) and DAC (CC).
        if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 &&
            marker != 0xCC) {
            if (i + 9 > n || len < 7) return false;
            *height = be16(i + 5);
            *width = be16(i + 7);
            return true;
        }
        if (len < 2) return false;
        i += 2 + len;
    }
    return false;
}

}  // namespace

Status check_sample(const df_msg_Header& header) { return check_status("Header", header.status); }

Status check_sample(const df_msg_RgbdFrame& f) {
    const char* t = "RgbdFrame";
    DF_RETURN_IF_ERROR(check_status(t, f.header.status));
    DF_RETURN_IF_ERROR(check_size(t, f.width, f.height, true));
    DF_RETURN_IF_ERROR(positive(t, "intrinsics.fx", f.intrinsics.fx, kMaxFocalPx));
    DF_RETURN_IF_ERROR(positive(t, "intrinsics.fy", f.intrinsics.fy, kMaxFocalPx));
    DF_RETURN_IF_ERROR(in_range(t, "intrinsics.cx", f.intrinsics.cx, 0, f.width));
    DF_RETURN_IF_ERROR(in_range(t, "intrinsics.cy", f.intrinsics.cy, 0, f.height));
    return positive(t, "depth_units_per_m", f.depth_units_per_m, kMaxDepthUnitsPerM);
}

Status check_sample(const df_msg_CompressedImage& c) {
    const char* t = "CompressedImage";
    DF_RETURN_IF_ERROR(check_status(t, c.header.status));
    DF_RETURN_IF_ERROR(
        at_most(t, "data length", c.data._length, df_msg_MAX_RGB_BYTES, "MAX_RGB_BYTES"));
    if (c.data._length > 0 && c.data._buffer == nullptr) {
        return bad(t, "data has length " + str(c.data._length) + " but no buffer");
    }
    const bool ok = c.header.status == df_msg_FRAME_OK;
    DF_RETURN_IF_ERROR(check_size(t, c.width, c.height, ok));
    DF_RETURN_IF_ERROR(at_most(t, "source_width", c.source_width, df_msg_MAX_WIDTH, "MAX_WIDTH"));
    DF_RETURN_IF_ERROR(
        at_most(t, "source_height", c.source_height, df_msg_MAX_HEIGHT, "MAX_HEIGHT"));
    if (!ok) return Status::ok();
    if (c.source_width == 0 || c.source_height == 0) {
        return bad(t, "source_width x source_height " + str(c.source_width) + "x" +
                          str(c.source_height) + " is empty");
    }
    const std::string format = get_name(c.format);
    if (format != "jpeg" && format != "png") {
        return bad(t, "format '" + format + "' is not \"jpeg\" or \"png\"");
    }
    uint32_t w = 0, h = 0;
    if (!encoded_size(c.data._buffer, c.data._length, format == "png", &w, &h)) {
        return bad(t, "data (" + str(c.data._length) + " bytes) has no " + format + " header");
    }
    if (w != c.width || h != c.height) {
        return bad(t, "data is a " + str(w) + "x" + str(h) + " " + format + ", width x height " +
                          str(c.width) + "x" + str(c.height));
    }
    return Status::ok();
}

Status check_sample(const df_msg_Detections& d) {
    const char* t = "Detections";
    DF_RETURN_IF_ERROR(check_status(t, d.header.status));
    DF_RETURN_IF_ERROR(at_most(t, "count", d.count, df_msg_MAX_DETECTIONS, "MAX_DETECTIONS"));
    for (uint32_t i = 0; i < d.count; ++i) {
        const df_msg_Detection& b = d.boxes[i];
        const std::string field = "boxes[" + str(i) + "]";
        DF_RETURN_IF_ERROR(check_box(t, field, b.x, b.y, b.w, b.h));
        DF_RETURN_IF_ERROR(check_class(t, field + ".class_id", b.class_id));
        DF_RETURN_IF_ERROR(in_range(t, field + ".score", b.score, 0, 1));
    }
    return Status::ok();
}

Status check_sample(const df_msg_GeometricSegments& g) {
    const char* t = "GeometricSegments";
    DF_RETURN_IF_ERROR(check_status(t, g.header.status));
    DF_RETURN_IF_ERROR(check_size(t, g.width, g.height, false));
    DF_RETURN_IF_ERROR(
        at_most(t, "segment_count", g.segment_count, df_msg_MAX_PIXELS, "MAX_PIXELS"));
    const size_t pixels = static_cast<size_t>(g.width) * g.height;
    const uint16_t* labels = g.labels;
    for (size_t i = 0; i < pixels; ++i) {
        if (labels[i] > g.segment_count) {
            return bad(t, "labels[" + str(i) + "] " + str(labels[i]) + " > segment_count " +
                              str(g.segment_count));
        }
    }
    return Status::ok();
}

Status check_sample(const df_msg_ObjectSegments& s) {
    const char* t = "ObjectSegments";
    DF_RETURN_IF_ERROR(check_status(t, s.header.status));
    DF_RETURN_IF_ERROR(check_size(t, s.width, s.height, false));
    DF_RETURN_IF_ERROR(
        at_most(t, "instance_count", s.instance_count, df_msg_MAX_INSTANCES, "MAX_INSTANCES"));
    DF_RETURN_IF_ERROR(check_bool(t, "detections_used", s.detections_used));
    const size_t pixels = static_cast<size_t>(s.width) * s.height;
    std::bitset<65536> ids;
    ids.set(0);  // background
    for (uint32_t i = 0; i < s.instance_count; ++i) {
        const df_msg_InstanceInfo& in = s.instances[i];
        const std::string field = "instances[" + str(i) + "]";
        if (in.instance_id == 0 || ids.test(in.instance_id)) {
            return bad(t, field + ".instance_id " + str(in.instance_id) +
                              (in.instance_id == 0 ? " is the background label 0" : " repeated"));
        }
        ids.set(in.instance_id);
        DF_RETURN_IF_ERROR(check_class(t, field + ".class_id", in.class_id));
        DF_RETURN_IF_ERROR(in_range(t, field + ".score", in.score, 0, 1));
        DF_RETURN_IF_ERROR(check_kind(t, field + ".kind", in.kind));
        DF_RETURN_IF_ERROR(check_box(t, field + ".box", in.box_x, in.box_y, in.box_w, in.box_h));
        DF_RETURN_IF_ERROR(
            at_most(t, field + ".pixel_count", in.pixel_count, pixels, "width x height"));
    }
    const uint16_t* labels = s.labels;
    for (size_t i = 0; i < pixels; ++i) {
        if (!ids.test(labels[i])) {
            return bad(t, "labels[" + str(i) + "] " + str(labels[i]) +
                              " is no instance_id of the " + str(s.instance_count) + " instances");
        }
    }
    return Status::ok();
}

Status check_sample(const df_msg_CameraPose& p) {
    const char* t = "CameraPose";
    DF_RETURN_IF_ERROR(check_status(t, p.header.status));
    const int32_t state = enum_value(p.state);
    if (state < df_msg_TRACKING_OK || state > df_msg_TRACKING_INITIALIZING) {
        return bad(t, "state " + str(state) + " not a TrackingState (0..2)");
    }
    return check_pose(t, "world_T_camera", p.world_T_camera, p.header.status == df_msg_FRAME_OK);
}

Status check_sample(const df_msg_ObjectPoses& p) {
    const char* t = "ObjectPoses";
    DF_RETURN_IF_ERROR(check_status(t, p.header.status));
    DF_RETURN_IF_ERROR(at_most(t, "count", p.count, df_msg_MAX_OBJECTS, "MAX_OBJECTS"));
    for (uint32_t i = 0; i < p.count; ++i) {
        const df_msg_ObjectPose& o = p.objects[i];
        const std::string field = "objects[" + str(i) + "]";
        DF_RETURN_IF_ERROR(check_class(t, field + ".class_id", o.class_id));
        DF_RETURN_IF_ERROR(check_kind(t, field + ".kind", o.kind));
        DF_RETURN_IF_ERROR(check_bool(t, field + ".visible", o.visible));
        DF_RETURN_IF_ERROR(check_bool(t, field + ".tracked", o.tracked));
        DF_RETURN_IF_ERROR(check_pose(t, field + ".world_T_object", o.world_T_object, true));
    }
    return Status::ok();
}

Status check_sample(const df_msg_MapCloud& m) {
    const char* t = "MapCloud";
    DF_RETURN_IF_ERROR(check_status(t, m.header.status));
    DF_RETURN_IF_ERROR(
        at_most(t, "point_count", m.point_count, df_msg_MAX_MAP_POINTS, "MAX_MAP_POINTS"));
    DF_RETURN_IF_ERROR(
        at_most(t, "object_count", m.object_count, df_msg_MAX_OBJECTS, "MAX_OBJECTS"));
    for (uint32_t i = 0; i < m.point_count; ++i) {
        const df_msg_MapPoint& p = m.points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return bad(t, "points[" + str(i) + "] is not finite");
        }
    }
    for (uint32_t i = 0; i < m.object_count; ++i) {
        const df_msg_ObjectExtent& e = m.objects[i];
        const std::string field = "objects[" + str(i) + "]";
        DF_RETURN_IF_ERROR(check_class(t, field + ".class_id", e.class_id));
        const float v[6] = {e.min_x, e.min_y, e.min_z, e.max_x, e.max_y, e.max_z};
        for (float x : v) DF_RETURN_IF_ERROR(in_range(t, field + " bounds", x, -1e4, 1e4));
        if (e.min_x > e.max_x || e.min_y > e.max_y || e.min_z > e.max_z) {
            return bad(t, field + ": min above max");
        }
    }
    return Status::ok();
}

Status check_sample(const df_msg_StageStatus& s) {
    const char* t = "StageStatus";
    DF_RETURN_IF_ERROR(check_status(t, s.header.status));
    DF_RETURN_IF_ERROR(
        at_most(t, "timing_count", s.timing_count, df_msg_MAX_STAGE_TIMINGS, "MAX_STAGE_TIMINGS"));
    for (uint32_t i = 0; i < s.timing_count; ++i) {
        DF_RETURN_IF_ERROR(in_range(t, "timings[" + str(i) + "].ms", s.timings[i].ms, 0, 86400e3));
    }
    return Status::ok();
}

Status check_sample(const TypeInfo& type, const void* sample) {
    const dds_topic_descriptor_t* d = type.descriptor;
    if (d == MsgTraits<df_msg_RgbdFrame>::descriptor())
        return check_sample(*static_cast<const df_msg_RgbdFrame*>(sample));
    if (d == MsgTraits<df_msg_CompressedImage>::descriptor())
        return check_sample(*static_cast<const df_msg_CompressedImage*>(sample));
    if (d == MsgTraits<df_msg_Detections>::descriptor())
        return check_sample(*static_cast<const df_msg_Detections*>(sample));
    if (d == MsgTraits<df_msg_GeometricSegments>::descriptor())
        return check_sample(*static_cast<const df_msg_GeometricSegments*>(sample));
    if (d == MsgTraits<df_msg_ObjectSegments>::descriptor())
        return check_sample(*static_cast<const df_msg_ObjectSegments*>(sample));
    if (d == MsgTraits<df_msg_CameraPose>::descriptor())
        return check_sample(*static_cast<const df_msg_CameraPose*>(sample));
    if (d == MsgTraits<df_msg_ObjectPoses>::descriptor())
        return check_sample(*static_cast<const df_msg_ObjectPoses*>(sample));
    if (d == MsgTraits<df_msg_MapCloud>::descriptor())
        return check_sample(*static_cast<const df_msg_MapCloud*>(sample));
    if (d == MsgTraits<df_msg_StageStatus>::descriptor())
        return check_sample(*static_cast<const df_msg_StageStatus*>(sample));
    return error(StatusCode::kInvalidArgument,
                 std::string("no sample check for type ") + type.name);
}

std::string writer_of(dds_entity_t reader, const dds_sample_info_t& info) {
    dds_builtintopic_endpoint_t* ep =
        dds_get_matched_publication_data(reader, info.publication_handle);
    if (ep == nullptr) return "writer handle " + std::to_string(info.publication_handle);
    std::ostringstream guid;
    guid << std::hex << std::setfill('0');
    for (int i = 0; i < 16; ++i) {
        guid << std::setw(2) << static_cast<int>(ep->key.v[i]) << (i % 4 == 3 && i < 15 ? ":" : "");
    }
    dds_builtintopic_free_endpoint(ep);
    return "writer " + guid.str();
}

bool RejectLog::report(const std::string& topic, const std::string& writer, uint64_t seq,
                       const Status& why) {
    const auto now = std::chrono::steady_clock::now().time_since_epoch();
    return report(topic, writer, seq, why,
                  std::chrono::duration_cast<std::chrono::nanoseconds>(now).count());
}

bool RejectLog::report(const std::string& topic, const std::string& writer, uint64_t seq,
                       const Status& why, int64_t now_ns) {
    ++total_;
    const std::string key = topic + '\n' + writer + '\n' + why.message();
    if (seen_.size() > 1024 && seen_.find(key) == seen_.end()) seen_.clear();  // bounded memory
    auto [it, fresh] = seen_.try_emplace(key);
    Entry& e = it->second;
    if (!fresh && now_ns - e.last_ns < interval_ns_) {
        ++e.left_out;
        return false;
    }
    std::string line = "seq=" + std::to_string(seq) + " sample rejected on " + topic + " from " +
                       writer + ": " + why.message();
    if (e.left_out > 0) {
        line += " (" + std::to_string(e.left_out) + " more like it not logged)";
    }
    log::warn(line);
    e.last_ns = now_ns;
    e.left_out = 0;
    return true;
}

}  // namespace df::dds
