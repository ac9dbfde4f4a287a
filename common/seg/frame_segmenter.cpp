#include "seg/frame_segmenter.hpp"

#include <algorithm>

#include "slam/frame.hpp"

namespace df::seg {

Result<GeometricSegmentation> segment_depth(const io::RgbdImage& image,
                                            const FrameSegmenterConfig& config) {
    slam::PreprocessConfig p = config.preprocess;
    p.pyramid_levels = 1;
    p.max_depth_m = config.geometric.max_depth_m;
    p.normal_baseline_px = config.geometric.normal_baseline_px;
    Result<slam::Frame> frame = slam::preprocess(image, p);
    if (!frame) return frame.status();
    const slam::FrameLevel& level = frame->levels[0];
    return segment_geometry(level.smoothed_vertex, level.normal, config.geometric);
}

dynamics::LabelImage to_label_image(const InstanceSegmentation& s) {
    dynamics::LabelImage out;
    out.labels = s.labels;
    for (const Instance& i : s.instances) {
        dynamics::InstanceInfo info;
        info.id = static_cast<uint16_t>(i.id);
        info.class_id = i.detection.class_id;
        info.score = i.detection.score;
        info.kind = i.kind == detect::ClassKind::kNonRigid ? dynamics::ObjectKind::kNonRigid
                                                           : dynamics::ObjectKind::kRigid;
        info.box = i.detection.box;
        info.pixels = i.pixels;
        out.instances.push_back(info);
    }
    return out;
}

void add_unsegmented_detections(const std::vector<detect::Detection>& detections,
                                const InstanceSegmentation& instances, const ClassKindOf& kind_of,
                                dynamics::LabelImage* out) {
    int next = 1;
    for (const Instance& i : instances.instances) next = std::max(next, i.id + 1);
    for (const detect::Detection& d : detections) {
        if (kind_of(d) != detect::ClassKind::kNonRigid) continue;
        bool segmented = false;
        for (const Instance& i : instances.instances)
            segmented = segmented || (i.detection.box == d.box && i.detection.class_id == d.class_id);
        if (segmented || next > 65535) continue;
        dynamics::InstanceInfo info;
        info.id = static_cast<uint16_t>(next++);
        info.class_id = d.class_id;
        info.score = d.score;
        info.kind = dynamics::ObjectKind::kNonRigid;
        info.box = d.box;
        info.pixels = 0;
        out->instances.push_back(info);
    }
}

Result<dynamics::FrameSegments> fuse_segments(const GeometricSegmentation& geometric,
                                              const std::vector<detect::Detection>& detections,
                                              const ClassKindOf& kind_of,
                                              const InstanceSegmentationConfig& config) {
    Result<InstanceSegmentation> instances = segment_instances(
        geometric.labels, geometric.count, cv::Mat(), detections, kind_of, config);
    if (!instances) return instances.status();
    dynamics::FrameSegments out;
    out.objects = to_label_image(*instances);
    add_unsegmented_detections(detections, *instances, kind_of, &out.objects);
    out.geometric = geometric.labels;
    out.geometric_count = geometric.count;
    return out;
}

}  // namespace df::seg
