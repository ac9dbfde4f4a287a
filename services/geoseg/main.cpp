// df_geoseg: the geometric segmentation service. Subscribes to <ns>/frames, publishes
// <ns>/geometric_segments and <ns>/stage_status for every frame (docs/segmentation.md). With
// --depth FILE it segments that one frame instead, without DDS, and writes a picture.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "config/validate.hpp"
#include "core/log.hpp"
#include "draw/pictures.hpp"
#include "geoseg_node.hpp"
#include "seg/frame_segmenter.hpp"
#include "service/frame_files.hpp"
#include "service/service.hpp"

namespace {

/// `df_geoseg --depth D [--color C]`: prints the segment count and writes the segments in colour
/// over the colour picture (or alone).
int segment_files(const df::service::FrameFileFlags& files,
                  const df::seg::FrameSegmenterConfig& config) {
    auto image = df::service::read_frame_files(files);
    if (!image) return df::log::error(image.status().message()), 1;
    auto segments = df::seg::segment_depth(*image, config);
    if (!segments) return df::log::error(files.depth, ": ", segments.status().message()), 1;
    const int covered = cv::countNonZero(segments->labels);
    std::printf("%s: %dx%d, %d geometric segments covering %.1f %% of the pixels\n",
                files.depth.c_str(), image->depth.cols, image->depth.rows, segments->count,
                100.0 * covered / static_cast<double>(image->depth.total()));
    auto written = df::service::write_picture(
        files, "segments",
        df::draw::colour_segments(segments->labels, files.color.empty() ? cv::Mat() : image->rgb));
    if (!written) return df::log::error(written.status().message()), 1;
    if (!written->empty()) std::printf("  wrote %s\n", written->c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    df::log::set_component("geoseg");
    CLI::App app{
        "df_geoseg: geometric segmentation of depth frames (Tateno et al. 2015) as a "
        "DDS service, or of one frame's files with --depth"};
    df::service::ConfigFlags flags;
    df::service::add_config_flags(app, &flags);
    df::service::FrameFileFlags files;
    df::service::add_frame_file_flags(app, &files);
    app.footer(df::config::options_help(df::config::GeosegServiceConfig::descriptor()));
    CLI11_PARSE(app, argc, argv);
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    // On the command line only warnings and errors go to stderr (not the configuration).
    if (files.given() && df::log::level() == df::log::Level::kInfo) {
        df::log::set_level(df::log::Level::kWarn);
    }
    df::config::GeosegServiceConfig config;
    if (!df::service::load_config(flags, &config)) return 2;
    df::seg::GeometricSegmentationConfig seg;
    df::slam::PreprocessConfig preprocess;
    if (auto s = df::geoseg_service::apply(config.params(), &seg, &preprocess); !s) {
        df::log::error(s.message());
        return 2;
    }
    if (files.given()) return segment_files(files, {preprocess, seg, {}});
    return df::service::run_node(config.dds(), [&](df::dds::Participant& p) {
        return df::geoseg_service::GeosegNode::create(config, seg, preprocess, p);
    });
}
