// df_fusion: joins geometric segments and detections by frame, publishes object segments for
// every frame (docs/segmentation.md). With --color C --depth D it does the whole chain for that
// one frame instead (geometric segmentation, detection, fusion), without DDS, and writes a
// picture of the object masks.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "boxes/box_source.hpp"
#include "config/apply_params.hpp"
#include "config/validate.hpp"
#include "core/log.hpp"
#include "detect/detector.hpp"
#include "draw/pictures.hpp"
#include "fusion_node.hpp"
#include "geoseg.pb.h"
#include "seg/frame_segmenter.hpp"
#include "service/frame_files.hpp"
#include "service/service.hpp"

namespace {

/// `df_fusion --color C --depth D`: the frame's object instances as df_geoseg, df_detector and
/// df_fusion would publish them (default geometric segmentation, the detector `detector_flags`
/// configure), printed one per line and drawn over the colour picture.
int fuse_files(const df::service::FrameFileFlags& files,
               const df::service::ConfigFlags& detector_flags,
               const df::fusion_service::FusionSettings& settings) {
    if (files.color.empty())
        return df::log::error("--depth needs --color (the detector's input)"), 2;
    df::seg::FrameSegmenterConfig seg;
    if (auto s = df::config::apply_params(df::config::GeosegParams(), &seg.geometric); !s) {
        return df::log::error(s.message()), 2;
    }
    seg.instances = settings.instance;
    df::config::DetectorServiceConfig detector_config;
    if (!df::service::load_config(detector_flags, &detector_config)) return 2;
    if (detector_config.model() == "simulated") {
        return df::log::error("--color/--depth need a YOLO model (model: yolov5, darknet or onnx)"),
               2;
    }
    auto detector = df::boxes::open_source(detector_config);
    if (!detector) return df::log::error("detector: ", detector.status().message()), 2;
    auto image = df::service::read_frame_files(files);
    if (!image) return df::log::error(image.status().message()), 1;

    auto boxes = (*detector)->detect(*image, 0);
    if (!boxes) return df::log::error(files.color, ": ", boxes.status().message()), 1;
    auto geometric = df::seg::segment_depth(*image, seg);
    if (!geometric) return df::log::error(files.depth, ": ", geometric.status().message()), 1;
    const auto kind_of = [&](const df::detect::Detection& d) {
        return df::detect::class_kind(settings.classes, d.class_name);
    };
    auto fused = df::seg::fuse_segments(*geometric, *boxes, kind_of, seg.instances);
    if (!fused) return df::log::error(fused.status().message()), 1;

    const df::dynamics::LabelImage& objects = fused->objects;
    std::printf("%s + %s: %zu detections, %d geometric segments, %zu object instances\n",
                files.color.c_str(), files.depth.c_str(), boxes->size(), geometric->count,
                objects.instances.size());
    for (const df::dynamics::InstanceInfo& i : objects.instances) {
        std::printf("  #%-3d %-14s %-9s %.2f  %6d px  box x %4.0f y %4.0f w %4.0f h %4.0f\n", i.id,
                    df::draw::class_name(i.class_id).c_str(), df::dynamics::to_string(i.kind),
                    i.score, i.pixels, i.box.x, i.box.y, i.box.width, i.box.height);
    }
    cv::Mat picture = image->rgb.clone();
    df::draw::tint_instances(objects, 1.f, &picture);
    auto written = df::service::write_picture(files, "instances", picture);
    if (!written) return df::log::error(written.status().message()), 1;
    if (!written->empty()) std::printf("  wrote %s\n", written->c_str());
    // The label image itself (16-bit, 0 none, else the instance's #id), as df_eval seg reads it.
    auto labels = df::service::write_image(files, "instance_labels", objects.labels);
    if (!labels) return df::log::error(labels.status().message()), 1;
    if (!labels->empty()) std::printf("  wrote %s\n", labels->c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("fusion");
    CLI::App app{
        "df_fusion: instance segmentation from detector boxes and geometric segments, "
        "joined by frame with a detection deadline; or of one frame's files with --color "
        "and --depth"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    df::service::FrameFileFlags files;
    df::service::add_frame_file_flags(app, &files);
    df::service::ConfigFlags detector_flags;
    app.add_option("--detector-config", detector_flags.config_path,
                   "with --color/--depth: the detector's configuration file (as df_detector's "
                   "--config; default YOLOv5s)");
    app.add_option("--detector-set", detector_flags.overrides,
                   "with --color/--depth: a detector option 'field: value' (repeatable)");
    app.footer(df::config::options_help(df::config::FusionServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    // On the command line only warnings and errors go to stderr (not the configuration).
    if (files.given() && df::log::level() == df::log::Level::kInfo) {
        df::log::set_level(df::log::Level::kWarn);
    }
    df::config::FusionServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    auto settings = df::fusion_service::settings_from(config);
    if (!settings) {
        df::log::error("configuration: ", settings.status().message());
        return 2;
    }
    if (files.given()) return fuse_files(files, detector_flags, *settings);
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::fusion_service::FusionNode::create(config, *settings, p);
    });
}
