#include "foxglove/messages.hpp"

#include <cstring>

#include "foxglove/cdr_writer.hpp"
#include "foxglove/idl_text.hpp"

namespace df::foxglove {
namespace {

// Enumerator values, in the order schemas.idl declares them.
constexpr uint32_t kLineLoop = 2;   // PointsAnnotationType
constexpr uint32_t kFloat32 = 7;    // NumericType
constexpr uint32_t kUint8 = 1;      // NumericType
constexpr uint32_t kLineStrip = 0;  // LineType
constexpr uint32_t kDeleteAll = 1;  // SceneEntityDeletionType

void time(CdrWriter& w, int64_t stamp_ns) {
    const int64_t ns = stamp_ns < 0 ? 0 : stamp_ns;
    w.u32(static_cast<uint32_t>(ns / 1000000000));
    w.u32(static_cast<uint32_t>(ns % 1000000000));
}

void colour(CdrWriter& w, const Rgba& c) {
    w.f64(c.r / 255.0);
    w.f64(c.g / 255.0);
    w.f64(c.b / 255.0);
    w.f64(c.a);
}

void vector3(CdrWriter& w, const Eigen::Vector3d& v) {
    w.f64(v.x());
    w.f64(v.y());
    w.f64(v.z());
}

void quaternion(CdrWriter& w, const Eigen::Quaterniond& q) {
    w.f64(q.x());
    w.f64(q.y());
    w.f64(q.z());
    w.f64(q.w());
}

void pose(CdrWriter& w, const Eigen::Vector3d& position,
          const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity()) {
    vector3(w, position);
    quaternion(w, orientation);
}

void point2(CdrWriter& w, double x, double y) {
    w.f64(x);
    w.f64(y);
}

/// The part every SceneEntity starts with, up to its primitive lists.
void entity_head(CdrWriter& w, int64_t stamp_ns, const std::string& frame_id,
                 const std::string& id) {
    time(w, stamp_ns);
    w.string(frame_id);
    w.string(id);
    w.i32(0);  // lifetime: 0 = until replaced or deleted
    w.u32(0);
    w.boolean(true);  // frame_locked: follows its frame as the frame's transform changes
    w.u32(0);         // metadata
    w.u32(0);         // arrows
}

}  // namespace

const char* idl_text() { return kIdlText; }

std::string object_frame(uint32_t id) { return "object_" + std::to_string(id); }

Result<Bytes> raw_image(int64_t stamp_ns, const std::string& frame_id, const cv::Mat& image) {
    const char* encoding = nullptr;
    switch (image.type()) {
        case CV_8UC3:
            encoding = "rgb8";
            break;
        case CV_8UC1:
            encoding = "mono8";
            break;
        case CV_16UC1:
            encoding = "16UC1";
            break;
        default:
            return error(StatusCode::kInvalidArgument,
                         "raw_image: only 8-bit 1- or 3-channel and 16-bit 1-channel images");
    }
    if (image.empty()) return error(StatusCode::kInvalidArgument, "raw_image: empty image");
    const size_t step = image.cols * image.elemSize();
    CdrWriter w;
    w.reserve(step * image.rows + 128);
    time(w, stamp_ns);
    w.string(frame_id);
    w.u32(static_cast<uint32_t>(image.cols));
    w.u32(static_cast<uint32_t>(image.rows));
    w.string(encoding);
    w.u32(static_cast<uint32_t>(step));
    w.u32(static_cast<uint32_t>(step * image.rows));
    for (int y = 0; y < image.rows; ++y) {
        const uint8_t* row = image.ptr<uint8_t>(y);
        w.append(row, step);
    }
    return w.take();
}

Bytes compressed_image(int64_t stamp_ns, const std::string& frame_id, const uint8_t* data,
                       size_t size, const std::string& format) {
    CdrWriter w;
    w.reserve(size + 64);
    time(w, stamp_ns);
    w.string(frame_id);
    w.bytes(data, size);
    w.string(format);
    return w.take();
}

Bytes image_annotations(int64_t stamp_ns, const std::vector<ImageBox>& boxes) {
    CdrWriter w;
    w.u32(0);  // circles
    w.u32(static_cast<uint32_t>(boxes.size()));
    for (const ImageBox& b : boxes) {
        time(w, stamp_ns);
        w.u32(kLineLoop);
        w.u32(4);
        point2(w, b.box.x, b.box.y);
        point2(w, b.box.x + b.box.width, b.box.y);
        point2(w, b.box.x + b.box.width, b.box.y + b.box.height);
        point2(w, b.box.x, b.box.y + b.box.height);
        colour(w, b.colour);          // outline_color
        w.u32(0);                     // outline_colors
        colour(w, Rgba{0, 0, 0, 0});  // fill_color: none
        w.f64(2.0);                   // thickness, pixels
    }
    size_t texts = 0;
    for (const ImageBox& b : boxes) texts += b.label.empty() ? 0 : 1;
    w.u32(static_cast<uint32_t>(texts));
    for (const ImageBox& b : boxes) {
        if (b.label.empty()) continue;
        time(w, stamp_ns);
        point2(w, b.box.x, std::max(12.0, static_cast<double>(b.box.y) - 2.0));
        w.string(b.label);
        w.f64(12.0);  // font_size, pixels
        colour(w, Rgba{255, 255, 255, 1});
        colour(w, Rgba{b.colour.r, b.colour.g, b.colour.b, 0.8});
    }
    return w.take();
}

Bytes frame_transform(int64_t stamp_ns, const std::string& parent, const std::string& child,
                      const Eigen::Isometry3d& parent_T_child) {
    CdrWriter w;
    time(w, stamp_ns);
    w.string(parent);
    w.string(child);
    vector3(w, parent_T_child.translation());
    quaternion(w, Eigen::Quaterniond(parent_T_child.rotation()).normalized());
    return w.take();
}

Bytes point_cloud(int64_t stamp_ns, const std::string& frame_id,
                  const std::vector<CloudPoint>& points) {
    constexpr uint32_t kStride = 16;
    CdrWriter w;
    w.reserve(points.size() * kStride + 256);
    time(w, stamp_ns);
    w.string(frame_id);
    pose(w, Eigen::Vector3d::Zero());
    w.u32(kStride);
    struct Field {
        const char* name;
        uint32_t offset, type;
    };
    const Field fields[] = {{"x", 0, kFloat32},   {"y", 4, kFloat32},    {"z", 8, kFloat32},
                            {"red", 12, kUint8},  {"green", 13, kUint8}, {"blue", 14, kUint8},
                            {"alpha", 15, kUint8}};
    w.u32(static_cast<uint32_t>(std::size(fields)));
    for (const Field& f : fields) {
        w.string(f.name);
        w.u32(f.offset);
        w.u32(f.type);
    }
    w.u32(static_cast<uint32_t>(points.size() * kStride));
    for (const CloudPoint& p : points) {
        uint8_t packed[kStride];
        std::memcpy(packed + 0, &p.x, 4);
        std::memcpy(packed + 4, &p.y, 4);
        std::memcpy(packed + 8, &p.z, 4);
        packed[12] = p.r;
        packed[13] = p.g;
        packed[14] = p.b;
        packed[15] = p.a;
        w.append(packed, kStride);
    }
    return w.take();
}

Bytes scene_update(int64_t stamp_ns, const std::vector<SceneBox>& boxes,
                   const std::vector<ScenePath>& paths) {
    CdrWriter w;
    w.u32(1);  // deletions: everything shown before
    time(w, stamp_ns);
    w.u32(kDeleteAll);
    w.string("");
    w.u32(static_cast<uint32_t>(boxes.size() + paths.size()));
    for (const SceneBox& b : boxes) {
        entity_head(w, stamp_ns, b.frame_id, b.id);
        w.u32(1);  // cubes
        pose(w, b.centre);
        vector3(w, b.size);
        colour(w, Rgba{b.colour.r, b.colour.g, b.colour.b, 0.35});
        w.u32(0);  // spheres
        w.u32(0);  // cylinders
        w.u32(1);  // lines: the box's edges, opaque
        w.u32(2);  // LINE_LIST
        pose(w, b.centre);
        w.f64(2.0);
        w.boolean(true);  // scale_invariant: thickness in pixels
        const Eigen::Vector3d h = b.size / 2;
        const int edges[12][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}, {4, 5}, {5, 7},
                                  {7, 6}, {6, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
        w.u32(24);
        for (const auto& e : edges) {
            for (int corner : e) {
                vector3(
                    w, Eigen::Vector3d((corner & 1) ? h.x() : -h.x(), (corner & 2) ? h.y() : -h.y(),
                                       (corner & 4) ? h.z() : -h.z()));
            }
        }
        colour(w, b.colour);
        w.u32(0);                        // colors
        w.u32(0);                        // indices
        w.u32(0);                        // triangles
        w.u32(b.label.empty() ? 0 : 1);  // texts
        if (!b.label.empty()) {
            pose(w, b.centre + Eigen::Vector3d(0, -h.y() - 0.05, 0));
            w.boolean(true);  // billboard
            w.f64(14.0);
            w.boolean(true);  // scale_invariant: font size in pixels
            colour(w, Rgba{b.colour.r, b.colour.g, b.colour.b, 1});
            w.string(b.label);
        }
        w.u32(0);  // models
    }
    for (const ScenePath& p : paths) {
        entity_head(w, stamp_ns, p.frame_id, p.id);
        w.u32(0);  // cubes
        w.u32(0);  // spheres
        w.u32(0);  // cylinders
        w.u32(1);  // lines
        w.u32(kLineStrip);
        pose(w, Eigen::Vector3d::Zero());
        w.f64(2.0);
        w.boolean(true);
        w.u32(static_cast<uint32_t>(p.points.size()));
        for (const Eigen::Vector3d& v : p.points) vector3(w, v);
        colour(w, p.colour);
        w.u32(0);
        w.u32(0);
        w.u32(0);  // triangles
        w.u32(0);  // texts
        w.u32(0);  // models
    }
    return w.take();
}

}  // namespace df::foxglove
