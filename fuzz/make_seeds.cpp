// Writes the seed corpora of the fuzz targets (a few small valid inputs each) under
// <dir>/<target>/: df_fuzz_seeds DIR. Generated rather than checked in, from the project's own
// writers, so the seeds follow the formats as they change.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "dds/cdr.hpp"
#include "dds/msg_convert.hpp"
#include "dds/msg_types.hpp"
#include "io/ply/ply.hpp"
#include "mcap/mcap_writer.hpp"
#include "sim/png.hpp"

namespace fs = std::filesystem;
using namespace df;

namespace {

using Bytes = std::vector<uint8_t>;

void put(const fs::path& dir, const std::string& name, const Bytes& bytes) {
    fs::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
}
void put(const fs::path& dir, const std::string& name, const std::string& text) {
    put(dir, name, Bytes(text.begin(), text.end()));
}
Bytes read_all(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

size_t type_index(const dds_topic_descriptor_t* d) {
    const auto& types = dds::all_types();
    for (size_t i = 0; i < types.size(); ++i)
        if (types[i].descriptor == d) return i;
    return 0;
}

/// Seed bytes for fuzz_samples: the type byte, then raw struct bytes (at most `max` of them) or
/// CDR (high bit set).
template <typename T>
Bytes sample_seed(const T& sample, bool cdr, size_t max = 2048) {
    Bytes out{static_cast<uint8_t>(type_index(dds::MsgTraits<T>::descriptor()) | (cdr ? 0x80 : 0))};
    if (cdr) {
        const Bytes c = dds::to_cdr(dds::MsgTraits<T>::descriptor(), &sample);
        out.insert(out.end(), c.begin(), c.end());
    } else {
        const auto* p = reinterpret_cast<const uint8_t*>(&sample);
        out.insert(out.end(), p, p + std::min(sizeof(T), max));
    }
    return out;
}

void samples(const fs::path& dir) {
    auto frame = std::make_unique<df_msg_RgbdFrame>();
    *frame = {};
    frame->width = 8;
    frame->height = 6;
    frame->intrinsics = {10, 10, 4, 3};
    frame->depth_units_per_m = 5000;
    put(dir, "frame_raw", sample_seed(*frame, false));
    df_msg_Detections det{};
    det.count = 2;
    det.image_width = 640;
    det.image_height = 480;
    det.boxes[0] = {1, 2, 30, 40, 0, 0.9f};
    det.boxes[1] = {100, 200, 30, 40, 56, 0.5f};
    put(dir, "detections_raw", sample_seed(det, false));
    put(dir, "detections_cdr", sample_seed(det, true));
    auto seg = std::make_unique<df_msg_GeometricSegments>();
    *seg = {};
    seg->width = 16;
    seg->height = 8;
    seg->segment_count = 3;
    for (int i = 0; i < 128; ++i) seg->labels[i] = static_cast<uint16_t>(i % 4);
    put(dir, "segments_raw", sample_seed(*seg, false));
    auto obj = std::make_unique<df_msg_ObjectSegments>();
    *obj = {};
    obj->width = 4;
    obj->height = 4;
    obj->instance_count = 1;
    obj->instances[0] = {1, 0, 0.8f, df_msg_OBJECT_NON_RIGID, 0, 0, 2, 2, 4};
    for (int i = 0; i < 4; ++i) obj->labels[i] = 1;
    put(dir, "objects_raw", sample_seed(*obj, false, 4096));
    df_msg_CameraPose pose{};
    pose.world_T_camera.qw = 1;
    pose.world_T_camera.tx = 0.5;
    put(dir, "pose_cdr", sample_seed(pose, true));
    df_msg_ObjectPoses poses{};
    poses.count = 1;
    poses.objects[0].world_T_object.qw = 1;
    put(dir, "object_poses_cdr", sample_seed(poses, true));
    df_msg_StageStatus st{};
    dds::set_name(st.stage, "slam");
    st.timing_count = 1;
    dds::set_name(st.timings[0].name, "total");
    st.timings[0].ms = 12.5f;
    put(dir, "status_cdr", sample_seed(st, true));
    // A colour_small sample with a real 16x12 JPEG.
    Bytes jpeg;
    cv::imencode(".jpg", cv::Mat(12, 16, CV_8UC3, cv::Scalar(20, 100, 200)), jpeg);
    df_msg_CompressedImage c{};
    c.width = 16;
    c.height = 12;
    c.source_width = 640;
    c.source_height = 480;
    dds::set_name(c.format, "jpeg");
    c.data._buffer = jpeg.data();
    c.data._length = c.data._maximum = static_cast<uint32_t>(jpeg.size());
    put(dir, "color_small_cdr", sample_seed(c, true));
}

void tum_lists(const fs::path& dir) {
    put(dir, "rgb.txt",
        "# color images\n# file: 'rgbd_dataset_freiburg3'\n# timestamp filename\n"
        "1305031102.175304 rgb/1305031102.175304.png\n1305031102.211214 "
        "rgb/1305031102.211214.png\n");
    put(dir, "associations.txt",
        "1305031102.175304 rgb/a.png 1305031102.160407 depth/a.png\n"
        "1305031102.211214 rgb/b.png 1305031102.226738 depth/b.png\n");
    put(dir, "ns.txt", "1700000000123456789 rgb/x.png\n1700000000156789012 rgb/y.png\n");
    put(dir, "odd.txt", "0 a\n0.000000001,b\n\t9223372036.854775807\tc\n1e9 d\nnan e\n");
}

void tum_images(const fs::path& dir) {
    cv::Mat rgb(6, 8, CV_8UC3), depth(6, 8, CV_16UC1);
    cv::randu(rgb, 0, 255);
    cv::randu(depth, 0, 8000);
    auto rgb_png = sim::encode_png(rgb, {});
    auto depth_png = sim::encode_png(depth, {});
    if (!rgb_png || !depth_png) return;
    Bytes both{0};
    both.insert(both.end(), rgb_png->begin(), rgb_png->end());
    both[0] = static_cast<uint8_t>(255 * both.size() / (both.size() + depth_png->size()));
    both.insert(both.end(), depth_png->begin(), depth_png->end());
    put(dir, "png_pair", both);
    Bytes jpeg;
    cv::imencode(".jpg", rgb, jpeg);
    Bytes mixed{
        static_cast<uint8_t>(255 * (jpeg.size() + 1) / (jpeg.size() + 1 + depth_png->size()))};
    mixed.insert(mixed.end(), jpeg.begin(), jpeg.end());
    mixed.insert(mixed.end(), depth_png->begin(), depth_png->end());
    put(dir, "jpeg_png_pair", mixed);
}

void mcap_files(const fs::path& dir, const fs::path& scratch) {
    for (auto compression :
         {mcap::WriterOptions::Compression::kNone, mcap::WriterOptions::Compression::kZstd}) {
        const fs::path file = scratch / "seed.mcap";
        mcap::WriterOptions options;
        options.compression = compression;
        options.chunk_size_bytes = 64;
        auto w = mcap::Writer::open(file.string(), options);
        if (!w) return;
        auto schema = (*w)->add_schema("df::msg::CameraPose", "omgidl", "struct CameraPose {};");
        if (!schema) return;
        auto channel = (*w)->add_channel(*schema, "df/camera_pose", "cdr", {{"k", "v"}});
        if (!channel) return;
        for (uint32_t i = 0; i < 3; ++i) {
            const Bytes data(20 + i, static_cast<uint8_t>(i));
            (void)(*w)->write(*channel, i, 1000 + i, 999 + i, data.data(), data.size());
        }
        if (!(*w)->close()) return;
        put(dir,
            compression == mcap::WriterOptions::Compression::kNone ? "plain.mcap" : "zstd.mcap",
            read_all(file));
    }
}

void ply_files(const fs::path& dir, const fs::path& scratch) {
    io::PointCloud cloud;
    cloud.positions = {{0, 0, 1}, {0.5, -0.25, 2}, {1, 1, 3}};
    cloud.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
    cloud.colours = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
    cloud.add_scalar("radius") = {0.01f, 0.02f, 0.03f};
    for (auto format : {io::PlyFormat::kAscii, io::PlyFormat::kBinaryLittleEndian}) {
        const fs::path file = scratch / "seed.ply";
        io::PlyWriteOptions options;
        options.format = format;
        options.comments = {"seed"};
        if (!io::write_ply(file.string(), cloud, options)) return;
        put(dir, format == io::PlyFormat::kAscii ? "ascii.ply" : "binary.ply", read_all(file));
    }
    put(dir, "faces.ply",
        "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
        "element vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
        "3 0 1 1\n0 0 0 1 2 3\n1 1 1 4 5 6\n");
}

void configs(const fs::path& dir) {
    // First byte: which service's configuration (fuzz_config.cpp).
    const auto seed = [&](const char* name, char which, const std::string& text) {
        put(dir, name, std::string(1, which) + text);
    };
    seed("slam", 0,
         "dds { ns: \"df\" domain_id: 3 transport: \"udp\" }\nstage: \"slam\"\nidle_exit_s: 2.5\n");
    seed("capture", 1, "folder: \"/tmp/x\"\nintrinsics_preset: \"fr1\"\nfx: 525\n");
    seed("geoseg", 2, "stage: \"geoseg\"\nidle_exit_s: 1 # comment\n");
    seed("detector", 3, "dds { peers: \"10.0.0.2\" peers: \"10.0.0.3\" }\n");
    seed("fusion", 4, "dds { ns: \"t\" }\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: df_fuzz_seeds DIR (writes DIR/<target>/...)\n";
        return 2;
    }
    const fs::path root = argv[1];
    const fs::path scratch = root / ".scratch";
    fs::create_directories(scratch);
    samples(root / "fuzz_samples");
    tum_lists(root / "fuzz_tum_lists");
    tum_images(root / "fuzz_tum_images");
    mcap_files(root / "fuzz_mcap", scratch);
    ply_files(root / "fuzz_ply", scratch);
    configs(root / "fuzz_config");
    fs::remove_all(scratch);
    std::cout << "seeds written under " << root << "\n";
    return 0;
}
