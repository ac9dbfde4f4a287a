#include "sim/writer.hpp"

#include <zlib.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>

#include "io/tum/trajectory.hpp"
#include "sim/models.hpp"
#include "sim/png.hpp"

namespace df::sim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string stamp_text(int64_t stamp_us) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, "%lld.%06lld", static_cast<long long>(stamp_us / 1000000),
                  static_cast<long long>(stamp_us % 1000000));
    return buffer;
}

Status write_text(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + path.string());
    return Status::ok();
}

/// PNG bytes of an image (see png.hpp; filters and strategies chosen by measurement on
/// generated frames: Sub + Huffman for noisy colour, plain deflate for depth, Up + run lengths
/// for instance masks).
Result<std::vector<uint8_t>> encode(const cv::Mat& image, PngFilter filter, int strategy,
                                    const std::string& what) {
    PngSettings settings;
    settings.filter = filter;
    settings.strategy = strategy;
    auto bytes = encode_png(image, settings);
    if (!bytes) return bytes.status().with_context(what);
    return bytes;
}

Status write_bytes(const fs::path& path, const std::vector<uint8_t>& bytes);

/// A model as docs/sequence_format.md describes it: binary little-endian PLY, float x y z nx ny nz
/// and uchar red green blue, one comment line.
Status write_model(const fs::path& path, const io::PointCloud& model, const std::string& comment) {
    io::PlyWriteOptions options;
    options.comments = {comment};
    return io::write_ply(path.string(), model, options);
}

/// Encodes and writes one frame's rgb, depth and instance images.
Status save_frame(const fs::path& root, const std::string& stamp, const cv::Mat& rgb,
                  const cv::Mat& depth, const cv::Mat& instance) {
    const auto rgb_png = encode(rgb, PngFilter::kSub, Z_HUFFMAN_ONLY, "rgb " + stamp);
    if (!rgb_png) return rgb_png.status();
    DF_RETURN_IF_ERROR(write_bytes(root / "rgb" / (stamp + ".png"), *rgb_png));
    const auto depth_png = encode(depth, PngFilter::kNone, Z_DEFAULT_STRATEGY, "depth " + stamp);
    if (!depth_png) return depth_png.status();
    DF_RETURN_IF_ERROR(write_bytes(root / "depth" / (stamp + ".png"), *depth_png));
    const auto instance_png = encode(instance, PngFilter::kUp, Z_RLE, "instances " + stamp);
    if (!instance_png) return instance_png.status();
    return write_bytes(root / "instances" / (stamp + ".png"), *instance_png);
}

Status write_bytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return error(StatusCode::kIoError, "cannot write " + path.string());
    return Status::ok();
}

const char* const kGeneratedFiles[] = {"rgb.txt",         "depth.txt",      "associations.txt",
                                       "groundtruth.txt", "intrinsics.txt", "instances.json",
                                       "sequence.json"};
const char* const kGeneratedFolders[] = {"rgb", "depth", "instances", "objects", "models"};

Status prepare_folder(const fs::path& root) {
    std::error_code ec;
    if (fs::exists(root, ec)) {
        if (!fs::is_directory(root, ec))
            return error(StatusCode::kInvalidArgument,
                         root.string() + " exists and is not a folder");
        const bool empty = fs::is_empty(root, ec);
        if (!empty && !fs::exists(root / "sequence.json", ec)) {
            return error(StatusCode::kInvalidArgument,
                         root.string() +
                             " is not empty and holds no sequence.json (not an "
                             "earlier output of df_make_sequence); choose a new folder");
        }
        for (const char* name : kGeneratedFolders) fs::remove_all(root / name, ec);
        for (const char* name : kGeneratedFiles) fs::remove(root / name, ec);
    }
    for (const char* name : kGeneratedFolders) {
        const fs::path dir = root / name;
        fs::create_directories(dir, ec);
        if (!fs::is_directory(dir, ec))
            return error(StatusCode::kIoError, "cannot create folder " + dir.string());
    }
    return Status::ok();
}

nlohmann::ordered_json sensor_json(const SensorConfig& c) {
    nlohmann::ordered_json j;
    j["depth_noise"] = {{"enabled", c.depth_noise},
                        {"sigma_m", "a + b (z - z0)^2"},
                        {"a_m", c.sigma_a_m},
                        {"b_per_m", c.sigma_b_per_m},
                        {"z0_m", c.sigma_z0_m}};
    j["disparity_quantisation"] = {{"enabled", c.quantisation},
                                   {"baseline_m", c.baseline_m},
                                   {"step_px", c.disparity_step_px}};
    j["projector_shadow"] = {{"enabled", c.projector_shadow}, {"margin_px", c.shadow_margin_px}};
    j["edge_holes"] = {{"enabled", c.edge_holes},
                       {"relative_jump", c.edge_jump},
                       {"probability", c.edge_hole_probability}};
    j["grazing_holes"] = {{"enabled", c.grazing_holes},
                          {"start_deg", c.grazing_start_deg},
                          {"full_deg", c.grazing_full_deg}};
    j["dropouts"] = {{"enabled", c.dropouts}, {"speckle_probability", c.speckle_probability}};
    j["range_m"] = {c.min_range_m, c.max_range_m};
    j["colour_noise"] = {{"enabled", c.colour_noise}, {"sigma_levels", c.colour_sigma}};
    j["exposure_changes"] = {{"enabled", c.exposure_changes}, {"amplitude", c.exposure_amplitude}};
    j["vignetting"] = {{"enabled", c.vignetting}, {"strength", c.vignetting_strength}};
    j["colour_blur"] = {{"enabled", c.colour_blur}, {"sigma_px", c.blur_sigma_px}};
    j["motion_blur"] = {{"enabled", c.motion_blur},
                        {"exposure_s", c.exposure_s},
                        {"samples", c.blur_samples}};
    return j;
}

/// A pose for a trajectory file; the quaternion's sign follows the previous pose's (q and -q are
/// the same rotation; a continuous sign keeps interpolating readers happy).
io::StampedPose stamped(double stamp_s, const Iso3& pose,
                        const std::vector<io::StampedPose>& previous) {
    io::StampedPose p;
    p.stamp_s = stamp_s;
    p.t = pose.translation();
    p.q = Eigen::Quaterniond(pose.linear()).normalized();
    const double dot = previous.empty() ? p.q.w() : previous.back().q.coeffs().dot(p.q.coeffs());
    if (dot < 0) p.q.coeffs() = -p.q.coeffs();
    return p;
}

/// objects/<name>.txt: world_T_object per frame, in the number format of groundtruth.txt.
Status write_object_trajectory(const fs::path& file, const std::string& name,
                               const std::vector<io::StampedPose>& poses) {
    std::string text = "# " + name +
                       ": object-to-world poses (world_T_object), p_world = R(q) p_object + t\n"
                       "# timestamp tx ty tz qx qy qz qw\n";
    for (const io::StampedPose& p : poses) {
        char line[512];
        std::snprintf(line, sizeof line, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.stamp_s,
                      p.t.x() + 0.0, p.t.y() + 0.0, p.t.z() + 0.0, p.q.x() + 0.0, p.q.y() + 0.0,
                      p.q.z() + 0.0, p.q.w() + 0.0);
        text += line;
    }
    return write_text(file, text);
}

}  // namespace

std::string sequence_json(const Sequence& s) {
    nlohmann::ordered_json j;
    j["generator"] = "df_make_sequence";
    j["generator_version"] = kGeneratorVersion;
    j["preset"] = s.preset;
    j["description"] = s.description;
    j["seed"] = s.seed;
    j["frames"] = s.frames;
    j["fps"] = s.fps;
    j["first_stamp_s"] = s.first_stamp_s;
    j["width"] = s.width;
    j["height"] = s.height;
    j["intrinsics"] = {{"fx", s.intrinsics.fx},
                       {"fy", s.intrinsics.fy},
                       {"cx", s.intrinsics.cx},
                       {"cy", s.intrinsics.cy}};
    j["depth_units_per_m"] = s.depth_units_per_m;
    j["camera_motion"] = to_string(s.camera.motion);
    j["world_frame"] = "z up, floor at z = 0";
    j["room_m"] = {{"min", {s.scene.room.lo.x(), s.scene.room.lo.y(), s.scene.room.lo.z()}},
                   {"max", {s.scene.room.hi.x(), s.scene.room.hi.y(), s.scene.room.hi.z()}}};
    j["sensor"] = sensor_json(s.sensor);
    j["static_model_spacing_m"] = s.static_model_spacing_m;
    j["object_model_spacing_m"] = s.object_model_spacing_m;
    j["missing_photos"] = s.missing_photos;
    return j.dump(2) + "\n";
}

std::string instances_json(const Sequence& s) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (size_t k = 0; k < s.scene.objects.size(); ++k) {
        const DynamicObject& o = s.scene.objects[k];
        nlohmann::ordered_json e;
        e["id"] = k + 1;
        e["name"] = o.name;
        e["class_id"] = o.class_id;
        e["class_name"] = o.class_name;
        e["kind"] = to_string(o.kind);
        if (o.kind == ObjectKind::kNonRigid) {
            e["model"] = nullptr;
        } else {
            e["model"] = "models/" + o.name + ".ply";
        }
        e["trajectory"] = "objects/" + o.name + ".txt";
        list.push_back(e);
    }
    nlohmann::ordered_json j;
    j["instances"] = list;
    return j.dump(2) + "\n";
}

Result<WriteReport> write_sequence(const Sequence& s, const std::string& folder,
                                   const WriteOptions& options) {
    const fs::path root(folder);
    DF_RETURN_IF_ERROR(prepare_folder(root));
    WriteReport report;
    RenderConfig config;
    config.width = s.width;
    config.height = s.height;
    config.intrinsics = s.intrinsics;
    config.threads = options.threads;

    std::string rgb_list = "# color images\n# timestamp filename\n";
    std::string depth_list = "# depth maps\n# timestamp filename\n";
    std::string associations;
    std::vector<io::StampedPose> camera_poses;
    std::vector<std::vector<io::StampedPose>> object_poses(s.scene.objects.size());
    // Frame i is encoded and written on a second thread while frame i + 1 is rendered.
    std::future<Status> saving;
    const auto t_frames = Clock::now();
    for (int i = 0; i < s.frames; ++i) {
        const FrameState state = frame_state(s, i);
        RenderBuffers buffers = render(s.scene, state, config);
        apply_motion_blur(s, i, config.threads, &buffers);
        SensorFrame sensor = apply_sensor(buffers, s.sensor, s.intrinsics, s.depth_units_per_m,
                                          s.seed, i, s.time_s(i), options.threads);
        const std::string stamp = stamp_text(s.stamp_us(i));
        const double stamp_s = static_cast<double>(s.stamp_us(i)) * 1e-6;
        if (saving.valid()) DF_RETURN_IF_ERROR(saving.get());
        saving = std::async(std::launch::async, [&root, stamp, rgb = std::move(sensor.rgb),
                                                 depth = std::move(sensor.depth),
                                                 instance = std::move(buffers.instance)] {
            return save_frame(root, stamp, rgb, depth, instance);
        });

        rgb_list += stamp + " rgb/" + stamp + ".png\n";
        depth_list += stamp + " depth/" + stamp + ".png\n";
        associations += stamp + " rgb/" + stamp + ".png " + stamp + " depth/" + stamp + ".png\n";
        camera_poses.push_back(stamped(stamp_s, state.world_T_camera, camera_poses));
        for (size_t k = 0; k < state.objects.size(); ++k)
            object_poses[k].push_back(
                stamped(stamp_s, state.objects[k].world_T_object, object_poses[k]));
        if (options.progress) options.progress(i + 1, s.frames);
    }
    if (saving.valid()) DF_RETURN_IF_ERROR(saving.get());
    report.frames_s = seconds_since(t_frames);
    DF_RETURN_IF_ERROR(write_text(root / "rgb.txt", rgb_list));
    DF_RETURN_IF_ERROR(write_text(root / "depth.txt", depth_list));
    DF_RETURN_IF_ERROR(write_text(root / "associations.txt", associations));
    DF_RETURN_IF_ERROR(io::write_tum_trajectory((root / "groundtruth.txt").string(), camera_poses));
    for (size_t k = 0; k < s.scene.objects.size(); ++k) {
        const std::string& name = s.scene.objects[k].name;
        DF_RETURN_IF_ERROR(
            write_object_trajectory(root / "objects" / (name + ".txt"), name, object_poses[k]));
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "# fx fy cx cy width height depth_units_per_m\n%.6f %.6f %.6f %.6f %d %d %.1f\n",
                  s.intrinsics.fx, s.intrinsics.fy, s.intrinsics.cx, s.intrinsics.cy, s.width,
                  s.height, s.depth_units_per_m);
    DF_RETURN_IF_ERROR(write_text(root / "intrinsics.txt", line));
    DF_RETURN_IF_ERROR(write_text(root / "instances.json", instances_json(s)));
    DF_RETURN_IF_ERROR(write_text(root / "sequence.json", sequence_json(s)));

    if (options.models) {
        const auto t0 = Clock::now();
        // The static model and the object models are independent: sample them in parallel.
        auto static_model = std::async(std::launch::async, [&] {
            return write_model(root / "models" / "static.ply",
                               sample_static_model(s.scene, s.static_model_spacing_m, s.seed),
                               "static scene surface, world frame, metres (df_make_sequence)");
        });
        Status objects_status = Status::ok();
        for (size_t k = 0; k < s.scene.objects.size() && objects_status.is_ok(); ++k) {
            const DynamicObject& o = s.scene.objects[k];
            if (o.kind == ObjectKind::kNonRigid) continue;
            objects_status =
                write_model(root / "models" / (o.name + ".ply"),
                            sample_object_model(s.scene, k, s.object_model_spacing_m, s.seed),
                            o.name + " surface, object frame, metres (df_make_sequence)");
        }
        const Status static_status = static_model.get();
        DF_RETURN_IF_ERROR(static_status);
        DF_RETURN_IF_ERROR(objects_status);
        report.models_s = seconds_since(t0);
    }
    return report;
}

}  // namespace df::sim
