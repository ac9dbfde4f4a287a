#include "dds/msg_convert.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace df::dds {
namespace {

// Views without the check: only for samples this file has checked or is filling.
cv::Mat rgb_of(const df_msg_RgbdFrame& frame) {
    return cv::Mat(frame.height, frame.width, CV_8UC3, const_cast<uint8_t*>(frame.rgb));
}
cv::Mat depth_of(const df_msg_RgbdFrame& frame) {
    return cv::Mat(frame.height, frame.width, CV_16UC1, const_cast<uint16_t*>(frame.depth));
}

}  // namespace

uint64_t wall_ns() {
    return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     std::chrono::system_clock::now().time_since_epoch())
                                     .count());
}

void fill_frame(const io::RgbdImage& image, const df_msg_Header& header, df_msg_RgbdFrame* frame) {
    const cv::Size size = image.rgb.size();
    if (image.rgb.type() != CV_8UC3 || image.depth.type() != CV_16UC1 ||
        image.depth.size() != size || size.width > static_cast<int>(df_msg_MAX_WIDTH) ||
        size.height > static_cast<int>(df_msg_MAX_HEIGHT)) {
        std::fprintf(stderr,
                     "fill_frame: image %dx%d (type %d, depth %dx%d type %d) does not fit "
                     "a frame sample (CV_8UC3 + CV_16UC1, at most %ux%u)\n",
                     size.width, size.height, image.rgb.type(), image.depth.cols, image.depth.rows,
                     image.depth.type(), df_msg_MAX_WIDTH, df_msg_MAX_HEIGHT);
        std::abort();
    }
    frame->header = header;
    frame->width = static_cast<uint16_t>(size.width);
    frame->height = static_cast<uint16_t>(size.height);
    frame->intrinsics.fx = static_cast<float>(image.intrinsics.fx);
    frame->intrinsics.fy = static_cast<float>(image.intrinsics.fy);
    frame->intrinsics.cx = static_cast<float>(image.intrinsics.cx);
    frame->intrinsics.cy = static_cast<float>(image.intrinsics.cy);
    frame->depth_units_per_m = static_cast<float>(image.depth_units_per_m);
    cv::Mat rgb = rgb_of(*frame);
    cv::Mat depth = depth_of(*frame);
    image.rgb.copyTo(rgb);
    image.depth.copyTo(depth);
}

cv::Mat rgb_view(const Checked<df_msg_RgbdFrame>& frame) { return rgb_of(*frame); }

cv::Mat depth_view(const Checked<df_msg_RgbdFrame>& frame) { return depth_of(*frame); }

io::RgbdImage to_image(const Checked<df_msg_RgbdFrame>& checked) {
    const df_msg_RgbdFrame& frame = *checked;
    io::RgbdImage image;
    image.rgb = rgb_of(frame).clone();
    image.depth = depth_of(frame).clone();
    image.depth_units_per_m = frame.depth_units_per_m;
    image.intrinsics = {frame.intrinsics.fx, frame.intrinsics.fy, frame.intrinsics.cx,
                        frame.intrinsics.cy};
    image.sensor_ns = static_cast<int64_t>(frame.header.sensor_ns);
    image.index = frame.header.seq;
    return image;
}

Result<io::RgbdImage> to_image(const df_msg_RgbdFrame& frame) {
    auto checked = dds::checked(frame);
    if (!checked) return checked.status();
    return to_image(*checked);
}

cv::Mat labels_of(const Checked<df_msg_GeometricSegments>& checked) {
    const df_msg_GeometricSegments& m = *checked;
    cv::Mat labels(m.height, m.width, CV_32SC1);
    const uint16_t* in = m.labels;
    for (int y = 0; y < m.height; ++y) {
        int32_t* row = labels.ptr<int32_t>(y);
        for (int x = 0; x < m.width; ++x) row[x] = *in++;
    }
    return labels;
}

namespace {

dynamics::ObjectKind kind_of(df_msg_ObjectKind k) {
    switch (k) {
        case df_msg_OBJECT_RIGID:
            return dynamics::ObjectKind::kRigid;
        case df_msg_OBJECT_NON_RIGID:
            return dynamics::ObjectKind::kNonRigid;
        default:
            return dynamics::ObjectKind::kUnknown;
    }
}

df_msg_ObjectKind msg_kind(dynamics::ObjectKind k) {
    switch (k) {
        case dynamics::ObjectKind::kRigid:
            return df_msg_OBJECT_RIGID;
        case dynamics::ObjectKind::kNonRigid:
            return df_msg_OBJECT_NON_RIGID;
        case dynamics::ObjectKind::kUnknown:
            break;
    }
    return df_msg_OBJECT_UNKNOWN;
}

}  // namespace

dynamics::LabelImage to_label_image(const Checked<df_msg_ObjectSegments>& checked) {
    const df_msg_ObjectSegments& m = *checked;
    dynamics::LabelImage out;
    if (m.width == 0 || m.height == 0) return out;
    out.labels = cv::Mat(m.height, m.width, CV_16UC1);
    std::memcpy(out.labels.data, m.labels, sizeof(uint16_t) * m.width * m.height);
    for (uint32_t i = 0; i < m.instance_count; ++i) {
        const df_msg_InstanceInfo& in = m.instances[i];
        dynamics::InstanceInfo info;
        info.id = in.instance_id;
        info.class_id = in.class_id;
        info.score = in.score;
        info.kind = kind_of(in.kind);
        info.box = cv::Rect2f(in.box_x, in.box_y, in.box_w, in.box_h);
        info.pixels = static_cast<int>(in.pixel_count);
        info.age = in.age_frames;
        out.instances.push_back(info);
    }
    return out;
}

size_t fill_object_segments(const dynamics::LabelImage& labels, const df_msg_Header& header,
                            df_msg_ObjectSegments* m) {
    m->header = header;
    m->detections_used = false;
    m->detections_seq = 0;
    m->instance_count = 0;
    m->width = m->height = 0;
    // The unused rows too: a loaned sample holds its chunk's old bytes, and a row's enum
    // must be valid for the sample to serialize (UDP, recordings).
    std::memset(m->instances, 0, sizeof(m->instances));
    if (labels.labels.empty() || labels.labels.type() != CV_16UC1 ||
        labels.labels.cols > static_cast<int>(df_msg_MAX_WIDTH) ||
        labels.labels.rows > static_cast<int>(df_msg_MAX_HEIGHT))
        return labels.instances.size();
    m->width = static_cast<uint16_t>(labels.labels.cols);
    m->height = static_cast<uint16_t>(labels.labels.rows);
    uint16_t* out = m->labels;
    for (int y = 0; y < labels.labels.rows; ++y) {
        const uint16_t* row = labels.labels.ptr<uint16_t>(y);
        out = std::copy(row, row + labels.labels.cols, out);
    }
    size_t dropped = 0;
    for (const dynamics::InstanceInfo& i : labels.instances) {
        if (m->instance_count >= df_msg_MAX_INSTANCES) {
            ++dropped;
            continue;
        }
        df_msg_InstanceInfo& info = m->instances[m->instance_count++];
        info.instance_id = i.id;
        info.class_id = i.class_id;
        info.score = i.score;
        info.kind = msg_kind(i.kind);
        info.box_x = i.box.x;
        info.box_y = i.box.y;
        info.box_w = i.box.width;
        info.box_h = i.box.height;
        info.pixel_count = static_cast<uint32_t>(std::max(0, i.pixels));
        info.age_frames = static_cast<uint16_t>(std::clamp(i.age, 0, 65535));
    }
    return dropped;
}

}  // namespace df::dds
