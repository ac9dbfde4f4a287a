#include "foxglove/scene.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "draw/pictures.hpp"

namespace df::foxglove {
namespace {

constexpr size_t kKeptColours = 8;  // frames of colour kept for their masks (fusion lags a few)

cv::Mat scaled(const cv::Mat& image, double scale, int interpolation) {
    if (scale >= 1.0) return image;
    cv::Mat out;
    cv::resize(image, out, cv::Size(), scale, scale, interpolation);
    return out;
}

Rgba to_rgba(const cv::Vec3b& c, double a = 1) {
    return Rgba{double(c[0]), double(c[1]), double(c[2]), a};
}

}  // namespace

ChannelSpec channel_spec(Channel channel, const std::string& prefix, const SceneOptions& o) {
    const char* image = o.jpeg_quality > 0 ? kCompressedImage : kRawImage;
    switch (channel) {
        case Channel::kColor:
            return {prefix + "/color", image};
        case Channel::kDepth:
            return {prefix + "/depth", kRawImage};
        case Channel::kDetections:
            return {prefix + "/detections", kImageAnnotations};
        case Channel::kMasks:
            return {prefix + "/masks", image};
        case Channel::kTransforms:
            return {prefix + "/tf", kFrameTransform};
        case Channel::kScene:
            return {prefix + "/scene", kSceneUpdate};
        case Channel::kMap:
            return {prefix + "/map", kPointCloud};
    }
    return {};
}

void SceneEncoder::image(Channel channel, int64_t stamp_ns, const cv::Mat& rgb,
                         std::vector<Message>* out) const {
    const cv::Mat small = scaled(rgb, options_.image_scale, cv::INTER_AREA);
    if (options_.jpeg_quality > 0) {
        cv::Mat bgr;
        cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
        std::vector<uint8_t> jpeg;
        cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.jpeg_quality});
        out->push_back(
            {channel, stamp_ns,
             compressed_image(stamp_ns, kCameraFrame, jpeg.data(), jpeg.size(), "jpeg")});
        return;
    }
    auto raw = raw_image(stamp_ns, kCameraFrame, small);
    if (raw) out->push_back({channel, stamp_ns, std::move(*raw)});
}

std::vector<Message> SceneEncoder::frame(uint64_t seq, int64_t stamp_ns,
                                         const io::RgbdImage& frame) {
    std::vector<Message> out;
    if (frame.rgb.empty()) return out;
    if (wanted(Channel::kMasks)) {
        // A copy: the caller's image may be a view of a sample it hands back after the call.
        colours_.emplace_back(seq, frame.rgb.clone());
        while (colours_.size() > kKeptColours) colours_.pop_front();
    }
    if (wanted(Channel::kColor)) image(Channel::kColor, stamp_ns, frame.rgb, &out);
    if (wanted(Channel::kDepth) && options_.depth && !frame.depth.empty()) {
        auto raw = raw_image(stamp_ns, kCameraFrame,
                             scaled(frame.depth, options_.image_scale, cv::INTER_NEAREST));
        if (raw) out.push_back({Channel::kDepth, stamp_ns, std::move(*raw)});
    }
    return out;
}

std::vector<Message> SceneEncoder::detections(int64_t stamp_ns,
                                              const std::vector<detect::Detection>& boxes,
                                              int width) {
    if (!wanted(Channel::kDetections) || width <= 0) return {};
    // Boxes in the pixels of the colour image as sent (scaled like it).
    const double s = std::min(1.0, options_.image_scale);
    std::vector<ImageBox> shown;
    for (const detect::Detection& d : boxes) {
        char label[96];
        std::snprintf(label, sizeof(label), "%s %.2f", d.class_name.c_str(), d.score);
        shown.push_back({cv::Rect2f(float(d.box.x * s), float(d.box.y * s), float(d.box.width * s),
                                    float(d.box.height * s)),
                         label, to_rgba(draw::id_colour(std::max(0, d.class_id)))});
    }
    return {{Channel::kDetections, stamp_ns, image_annotations(stamp_ns, shown)}};
}

std::vector<Message> SceneEncoder::instances(uint64_t seq, int64_t stamp_ns,
                                             const dynamics::LabelImage& labels) {
    std::vector<Message> out;
    if (!wanted(Channel::kMasks) || labels.labels.empty()) return out;
    cv::Mat picture;
    for (const auto& [s, rgb] : colours_) {
        if (s == seq && rgb.size() == labels.labels.size()) picture = rgb.clone();
    }
    if (picture.empty()) picture = cv::Mat::zeros(labels.labels.size(), CV_8UC3);
    draw::tint_instances(labels, 1.f, &picture);
    image(Channel::kMasks, stamp_ns, picture, &out);
    return out;
}

Message SceneEncoder::scene(int64_t stamp_ns) const {
    std::vector<SceneBox> boxes;
    for (const auto& [id, b] : bounds_) {
        if (tracked_.count(id) == 0) continue;  // only objects SLAM still reports
        const cv::Vec3b c = draw::id_colour(static_cast<int>(id));
        boxes.push_back({object_frame(id), object_frame(id), ((b.min + b.max) / 2).cast<double>(),
                         (b.max - b.min).cast<double>(),
                         "#" + std::to_string(id) + " " + draw::class_name(b.class_id),
                         to_rgba(c)});
    }
    std::vector<ScenePath> paths;
    if (path_.size() >= 2) {
        paths.push_back(
            {"camera_path", kWorldFrame, {path_.begin(), path_.end()}, Rgba{255, 140, 0, 1}});
    }
    return {Channel::kScene, stamp_ns, scene_update(stamp_ns, boxes, paths)};
}

std::vector<Message> SceneEncoder::camera_pose(int64_t stamp_ns,
                                               const Eigen::Isometry3d& world_T_camera) {
    std::vector<Message> out;
    path_.push_back(world_T_camera.translation());
    while (path_.size() > options_.max_path_poses) path_.pop_front();
    if (wanted(Channel::kTransforms)) {
        out.push_back({Channel::kTransforms, stamp_ns,
                       frame_transform(stamp_ns, kWorldFrame, kCameraFrame, world_T_camera)});
    }
    if (wanted(Channel::kScene)) out.push_back(scene(stamp_ns));
    return out;
}

std::vector<Message> SceneEncoder::object_poses(int64_t stamp_ns,
                                                const std::vector<ObjectState>& objects) {
    std::vector<Message> out;
    tracked_.clear();
    for (const ObjectState& o : objects) {
        tracked_[o.id] = o.tracked;
        if (!wanted(Channel::kTransforms)) continue;
        out.push_back(
            {Channel::kTransforms, stamp_ns,
             frame_transform(stamp_ns, kWorldFrame, object_frame(o.id), o.world_T_object)});
    }
    return out;
}

std::vector<Message> SceneEncoder::map(int64_t stamp_ns, const std::vector<CloudPoint>& points,
                                       const std::vector<ObjectBounds>& bounds) {
    for (const ObjectBounds& b : bounds) bounds_[b.id] = b;
    if (!wanted(Channel::kMap)) return {};
    return {{Channel::kMap, stamp_ns, point_cloud(stamp_ns, kWorldFrame, points)}};
}

}  // namespace df::foxglove
