// Dynamic SLAM over a TUM RGB-D folder with the installed DetectFusion libraries
// (docs/library.md): each depth image is segmented geometrically, then the SLAM system tracks it
// with what moves left out and fuses the rest into its surfel map. Writes the trajectory in TUM
// format.   tum_slam <folder> <trajectory.txt> [fr1|fr2|fr3|7scenes, when no intrinsics.txt]
#include <cstdio>
#include <utility>

#include "io/tum/intrinsics_file.hpp"
#include "io/tum/tum_folder.hpp"
#include "seg/frame_segmenter.hpp"
#include "slam_system/slam_system.hpp"

int fail(const df::Status& status) {
    std::fprintf(stderr, "tum_slam: %s\n", status.message().c_str());
    return 1;
}

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s <tum folder> <trajectory.txt> [preset]\n", argv[0]);
        return 2;
    }
    auto folder = df::io::tum_folder_config(argv[1], argc > 3 ? argv[3] : "fr3");
    if (!folder) return fail(folder.status());
    auto source = df::io::TumFolderSource::open(*folder);
    if (!source) return fail(source.status());
    auto slam = df::slam::SlamSystem::create(df::slam::SystemConfig{});
    if (!slam) return fail(slam.status());
    const df::seg::FrameSegmenterConfig seg;  // no detector: no class makes an object instance
    const auto no_classes = [](const df::detect::Detection&) {
        return df::detect::ClassKind::kIgnored;
    };
    for (auto read = (*source)->next(); read.kind != df::io::FrameRead::Kind::kEnd;
         read = (*source)->next()) {
        if (read.kind == df::io::FrameRead::Kind::kBadFrame) {
            std::fprintf(stderr, "skipped: %s\n", read.error.c_str());
            continue;
        }
        // Motion segmentation grows what moved by these segments; without them it works alone.
        df::dynamics::FrameSegments segments;
        if (auto geometric = df::seg::segment_depth(read.image, seg)) {
            auto fused = df::seg::fuse_segments(*geometric, {}, no_classes, seg.instances);
            if (fused) segments = std::move(fused).value();
        }
        auto report = slam->process(read.image, segments);
        if (!report) std::fprintf(stderr, "%s\n", report.status().message().c_str());
    }
    if (df::Status written = slam->write_trajectory(argv[2]); !written) return fail(written);
    std::printf("%llu frames (%llu lost), trajectory %s\n",
                static_cast<unsigned long long>(slam->frames()),
                static_cast<unsigned long long>(slam->lost_frames()), argv[2]);
    return 0;
}
