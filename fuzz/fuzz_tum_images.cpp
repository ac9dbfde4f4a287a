// The TUM image read path: a folder whose rgb and depth images are the fuzz input (PNG or JPEG
// bytes, split in two), read by TumFolderSource (header check before decoding, decode, type and
// size checks). Property: a frame it returns is CV_8UC3 + CV_16UC1 of one size within
// 640x480; anything else is a bad frame with a message, never a crash or a huge allocation.
// The PNG encoder of the generator (sim::encode_png) must give back the pixels it was given.
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "fuzz_util.hpp"
#include "io/tum/tum_folder.hpp"
#include "sim/png.hpp"

using namespace df;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& path, const uint8_t* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

fs::path make_folder() {
    const fs::path dir = fs::path(fuzz::as_file("tum_images_dir", nullptr, 0)).string() + ".d";
    fs::create_directories(dir / "rgb");
    fs::create_directories(dir / "depth");
    std::ofstream(dir / "rgb.txt") << "1.0 rgb/1.png\n";
    std::ofstream(dir / "depth.txt") << "1.0 depth/1.png\n";
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const fs::path dir = make_folder();
    // First byte: where the input splits into the rgb and the depth file (in 1/255ths).
    if (size < 1) return 0;
    const size_t split = 1 + (size - 1) * data[0] / 255;
    write(dir / "rgb" / "1.png", data + 1, split - 1);
    write(dir / "depth" / "1.png", data + split, size - split);

    io::TumFolderConfig config;
    config.folder = dir.string();
    config.intrinsics = {525, 525, 319.5, 239.5};
    auto source = io::TumFolderSource::open(config);
    if (!source) return 0;
    const io::FrameRead read = (*source)->next();
    if (read.kind != io::FrameRead::Kind::kFrame) return 0;
    const cv::Mat& rgb = read.image.rgb;
    const cv::Mat& depth = read.image.depth;
    DF_FUZZ_CHECK(rgb.type() == CV_8UC3 && depth.type() == CV_16UC1);
    DF_FUZZ_CHECK(rgb.size() == depth.size());
    DF_FUZZ_CHECK(rgb.cols >= 1 && rgb.cols <= 640 && rgb.rows >= 1 && rgb.rows <= 480);

    auto png = sim::encode_png(depth, {});
    DF_FUZZ_CHECK(png.is_ok());
    const cv::Mat back = cv::imdecode(*png, cv::IMREAD_UNCHANGED);
    DF_FUZZ_CHECK(back.type() == CV_16UC1 && back.size() == depth.size());
    DF_FUZZ_CHECK(cv::norm(back, depth, cv::NORM_INF) == 0);
    return 0;
}
