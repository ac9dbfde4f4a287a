// Generated folders checked through the files alone (docs/sequence_format.md): layout,
// determinism, and ground truth that agrees with itself across views, masks and models.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "io/ply/ply.hpp"
#include "io/tum/tum_folder.hpp"
#include "sim/sensor.hpp"
#include "sim/sequence.hpp"
#include "sim/writer.hpp"
#include "sim_test_util.hpp"

namespace df::sim {
namespace {

namespace fs = std::filesystem;
using test::quantile;
using test::SequenceFolder;
using test::TempFolder;

/// Writes a preset at a small size into `folder`; fails the test on error.
void generate(const std::string& preset, const std::string& folder, int frames, int width,
              int height, bool noise, uint64_t seed = 1, int threads = 2,
              double static_spacing = 0.02) {
    PresetOptions o;
    o.frames = frames;
    o.width = width;
    o.height = height;
    o.noise = noise;
    o.seed = seed;
    auto s = make_sequence(preset, o);
    ASSERT_TRUE(s.is_ok()) << s.status().to_string();
    s->static_model_spacing_m = static_spacing;
    WriteOptions w;
    w.threads = threads;
    auto r = write_sequence(*s, folder, w);
    ASSERT_TRUE(r.is_ok()) << r.status().to_string();
}

/// Folders shared by the tests of this file (generated once).
class SimFolder : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        exact_ = new TempFolder("exact");
        noisy_ = new TempFolder("noisy");
        objects_ = new TempFolder("objects");
        generate("walking_xyz", exact_->str(), 40, 320, 240, false);
        generate("walking_xyz", noisy_->str(), 40, 320, 240, true);
        generate("default", objects_->str(), 120, 320, 240, false);
    }
    static void TearDownTestSuite() {
        delete exact_;
        delete noisy_;
        delete objects_;
    }
    static TempFolder* exact_;
    static TempFolder* noisy_;
    static TempFolder* objects_;
};
TempFolder* SimFolder::exact_ = nullptr;
TempFolder* SimFolder::noisy_ = nullptr;
TempFolder* SimFolder::objects_ = nullptr;

TEST_F(SimFolder, LayoutFollowsTheSequenceFormat) {
    const std::string root = objects_->str();
    const SequenceFolder f = SequenceFolder::read(root);
    ASSERT_EQ(f.stamps.size(), 120u);
    EXPECT_EQ(f.stamps[0], "1.000000");
    EXPECT_EQ(f.stamps[1], "1.033333");
    EXPECT_EQ(f.width, 320);
    EXPECT_EQ(f.height, 240);
    EXPECT_EQ(f.units_per_m, 5000);
    EXPECT_NEAR(f.k.fx, 535.4 / 2, 1e-6);
    EXPECT_EQ(f.world_T_camera.size(), 120u);
    // The project's own TUM reader opens it.
    io::TumFolderConfig config;
    config.folder = root;
    config.intrinsics = f.k;  // the 320x240 sequence's own (fr3's are refused for its size)
    auto source = io::TumFolderSource::open(config);
    ASSERT_TRUE(source.is_ok()) << source.status().to_string();
    EXPECT_EQ((*source)->size(), 120);
    EXPECT_TRUE((*source)->list_errors().empty());
    const cv::Mat rgb = f.png("rgb", 5), depth = f.png("depth", 5), inst = f.png("instances", 5);
    EXPECT_EQ(rgb.type(), CV_8UC3);
    EXPECT_EQ(depth.type(), CV_16UC1);
    EXPECT_EQ(inst.type(), CV_16UC1);
    EXPECT_EQ(inst.size(), cv::Size(320, 240));

    const auto instances = nlohmann::json::parse(test::read_text(root + "/instances.json"));
    std::map<std::string, std::string> kinds;
    for (const auto& e : instances["instances"]) {
        const std::string name = e["name"];
        kinds[name] = e["kind"];
        const auto poses = SequenceFolder::poses(root + "/" + e["trajectory"].get<std::string>());
        EXPECT_EQ(poses.size(), 120u) << name;
        if (e["kind"] == "non_rigid") {
            EXPECT_TRUE(e["model"].is_null());
        } else {
            auto model = io::read_ply(root + "/" + e["model"].get<std::string>());
            ASSERT_TRUE(model.is_ok()) << model.status().to_string();
            EXPECT_GT(model->size(), 1000u);
            EXPECT_EQ(model->normals.size(), model->size()) << name;
            EXPECT_EQ(model->colours.size(), model->size()) << name;
        }
    }
    EXPECT_EQ(kinds["car_1"], "rigid");
    EXPECT_EQ(kinds["person_1"], "non_rigid");
    EXPECT_EQ(kinds["unknown_1"], "unknown");
    for (const auto& e : instances["instances"]) {
        const std::map<std::string, int> expected = {
            {"car_1", 2}, {"person_1", 0}, {"unknown_1", -1}};
        EXPECT_EQ(e["class_id"].get<int>(), expected.at(e["name"].get<std::string>()));
    }
    const auto meta = nlohmann::json::parse(test::read_text(root + "/sequence.json"));
    EXPECT_EQ(meta["preset"], "default");
    EXPECT_EQ(meta["seed"], 1);
    EXPECT_FALSE(meta["sensor"]["depth_noise"]["enabled"].get<bool>());
}

/// Static-scene pixels of frame A, moved into frame B with the true poses, land on B's depth.
/// B's depth is read by bilinear interpolation of inverse depth (exact on planes) where its four
/// neighbours are static, valid, continuous and (noise-free) on one plane, i.e. inverse depth is
/// affine over them. Returns |residuals| and residual / sigma.
void reproject(const SequenceFolder& f, size_t a, size_t b, bool planar_only,
               std::vector<double>* abs_m, std::vector<double>* normalised) {
    const cv::Mat za = f.depth_m(a), zb = f.depth_m(b);
    const cv::Mat ia = f.png("instances", a), ib = f.png("instances", b);
    const Eigen::Isometry3d b_T_a = f.world_T_camera[b].inverse() * f.world_T_camera[a];
    const SensorConfig sensor;
    for (int y = 0; y < za.rows; y += 2)
        for (int x = 0; x < za.cols; x += 2) {
            const float z = za.at<float>(y, x);
            if (z <= 0 || ia.at<uint16_t>(y, x) != 0) continue;
            const Eigen::Vector3d p = b_T_a * f.back_project(x, y, z);
            if (p.z() < 0.3) continue;
            const double u = f.k.fx * p.x() / p.z() + f.k.cx, v = f.k.fy * p.y() / p.z() + f.k.cy;
            const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
            if (u0 < 0 || v0 < 0 || u0 + 1 >= zb.cols || v0 + 1 >= zb.rows) continue;
            double inv[4], zmin = 1e9, zmax = 0;
            bool ok = true;
            for (int k = 0; k < 4; ++k) {
                const int xx = u0 + (k & 1), yy = v0 + (k >> 1);
                const float zz = zb.at<float>(yy, xx);
                ok = ok && zz > 0 && ib.at<uint16_t>(yy, xx) == 0;
                inv[k] = zz > 0 ? 1.0 / zz : 0;
                zmin = std::min<double>(zmin, zz), zmax = std::max<double>(zmax, zz);
            }
            if (!ok || zmax > 1.03 * zmin) continue;
            // Noise-free: also leave out quads across a small step (a picture on its wall), which
            // the affine test cannot see when the step runs along the quad's side.
            if (planar_only && (zmax > 1.005 * zmin ||
                                std::abs(inv[0] + inv[3] - inv[1] - inv[2]) > 1e-4 * inv[0]))
                continue;
            const double fu = u - u0, fv = v - v0;
            const double inv_b = (inv[0] * (1 - fu) + inv[1] * fu) * (1 - fv) +
                                 (inv[2] * (1 - fu) + inv[3] * fu) * fv;
            const double r = 1.0 / inv_b - p.z();
            abs_m->push_back(std::abs(r));
            const double q = quantisation_step(sensor, native_fx(sensor, f.k.fx, f.width), p.z());
            const double sigma = std::sqrt(std::pow(depth_sigma(sensor, p.z()), 2) + q * q / 12);
            normalised->push_back(std::abs(r) / (std::sqrt(2.0) * sigma));
        }
}

TEST_F(SimFolder, StaticPixelsAgreeAcrossViewsWithoutNoise) {
    const SequenceFolder f = SequenceFolder::read(exact_->str());
    std::vector<double> abs_m, normalised;
    for (size_t a : {0, 10, 20}) reproject(f, a, a + 19, true, &abs_m, &normalised);
    const double median = quantile(abs_m, 0.5), p95 = quantile(abs_m, 0.95);
    std::printf("noise-free: %zu points, |residual| median %.3f mm, p95 %.3f mm, p99 %.3f mm\n",
                abs_m.size(), 1e3 * median, 1e3 * p95, 1e3 * quantile(abs_m, 0.99));
    ASSERT_GT(abs_m.size(), 10000u);
    // Depth is stored in 0.2 mm steps; what remains are points that B sees behind a nearer
    // static surface (occlusion), about 1 %.
    EXPECT_LT(median, 0.1e-3);
    EXPECT_LT(p95, 0.3e-3);
}

TEST_F(SimFolder, StaticPixelsAgreeAcrossViewsWithinTheNoiseModel) {
    const SequenceFolder f = SequenceFolder::read(noisy_->str());
    std::vector<double> abs_m, normalised;
    for (size_t a : {0, 10, 20}) reproject(f, a, a + 19, false, &abs_m, &normalised);
    const double median = quantile(normalised, 0.5), p95 = quantile(normalised, 0.95);
    std::printf(
        "noisy: %zu points, |residual| / sigma median %.2f, p95 %.2f (|residual| median %.1f mm)\n",
        normalised.size(), median, p95, 1e3 * quantile(abs_m, 0.5));
    ASSERT_GT(normalised.size(), 10000u);
    // A Gaussian's |x| / sigma has median 0.67 and 95th percentile 1.96.
    EXPECT_LT(median, 0.9);
    EXPECT_LT(p95, 2.6);
}

/// Pixels of a rigid object's mask, back-projected with the camera pose and moved into the object
/// frame with its pose, lie on its model; static pixels lie on the static model and on no object.
TEST_F(SimFolder, MasksDepthPosesAndModelsAgree) {
    const std::string root = objects_->str();
    const SequenceFolder f = SequenceFolder::read(root);
    const auto instances = nlohmann::json::parse(test::read_text(root + "/instances.json"));
    auto static_model = io::read_ply(root + "/models/static.ply");
    ASSERT_TRUE(static_model.is_ok());
    const test::PointIndex static_index(static_model->positions, 0.05);
    struct Rigid {
        int id;
        std::string name;
        std::vector<Eigen::Isometry3d> poses;
        std::unique_ptr<test::PointIndex> index;
    };
    std::vector<Rigid> rigid;
    for (const auto& e : instances["instances"]) {
        if (e["model"].is_null()) continue;
        auto model = io::read_ply(root + "/" + e["model"].get<std::string>());
        ASSERT_TRUE(model.is_ok());
        rigid.push_back({e["id"].get<int>(), e["name"].get<std::string>(),
                         SequenceFolder::poses(root + "/" + e["trajectory"].get<std::string>()),
                         std::make_unique<test::PointIndex>(model->positions, 0.03)});
    }
    ASSERT_EQ(rigid.size(), 2u);
    std::map<int, std::vector<double>> on_model;
    std::vector<double> static_on_static;
    int static_pixels = 0, static_on_object = 0;
    for (size_t i = 0; i < f.stamps.size(); i += 10) {
        const cv::Mat z = f.depth_m(i), ids = f.png("instances", i);
        for (int y = 0; y < z.rows; y += 2)
            for (int x = 0; x < z.cols; x += 2) {
                const float d = z.at<float>(y, x);
                if (d <= 0) continue;
                const Eigen::Vector3d world = f.world_T_camera[i] * f.back_project(x, y, d);
                const int id = ids.at<uint16_t>(y, x);
                if (id == 0) {
                    ++static_pixels;
                    static_on_static.push_back(static_index.distance(world));
                    for (const Rigid& r : rigid)
                        if (r.index->distance(r.poses[i].inverse() * world) < 0.004)
                            ++static_on_object;
                }
                for (const Rigid& r : rigid)
                    if (r.id == id)
                        on_model[id].push_back(r.index->distance(r.poses[i].inverse() * world));
            }
    }
    for (const Rigid& r : rigid) {
        const auto& d = on_model[r.id];
        std::printf("%s: %zu mask pixels, distance to model median %.2f mm, p95 %.2f mm\n",
                    r.name.c_str(), d.size(), 1e3 * quantile(d, 0.5), 1e3 * quantile(d, 0.95));
        ASSERT_GT(d.size(), 300u) << r.name;
        EXPECT_LT(quantile(d, 0.5), 0.003) << r.name;
        EXPECT_LT(quantile(d, 0.95), 0.005) << r.name;
    }
    std::printf(
        "static pixels: %d, distance to static model median %.1f mm, p99 %.1f mm; on an "
        "object model: %d\n",
        static_pixels, 1e3 * quantile(static_on_static, 0.5),
        1e3 * quantile(static_on_static, 0.99), static_on_object);
    EXPECT_LT(quantile(static_on_static, 0.99), 0.02);
    EXPECT_LT(static_on_object, 0.002 * static_pixels);
}

TEST_F(SimFolder, StaticModelCoversTheRoom) {
    io::PlyReadInfo info;
    auto model = io::read_ply(objects_->str() + "/models/static.ply", &info);
    ASSERT_TRUE(model.is_ok());
    ASSERT_EQ(model->normals.size(), model->size());
    EXPECT_EQ(info.format, io::PlyFormat::kBinaryLittleEndian);
    Eigen::AlignedBox3f box;
    int floor = 0, ceiling = 0;
    for (size_t i = 0; i < model->size(); ++i) {
        const Eigen::Vector3f p = model->positions[i].cast<float>();
        const Eigen::Vector3f& n = model->normals[i];
        box.extend(p);
        floor += p.z() < 1e-4f && n.z() > 0.99f;
        ceiling += p.z() > 2.8f - 1e-4f && n.z() < -0.99f;
    }
    const auto meta = nlohmann::json::parse(test::read_text(objects_->str() + "/sequence.json"));
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(box.min()[i], meta["room_m"]["min"][i].get<double>(), 0.02);
        EXPECT_NEAR(box.max()[i], meta["room_m"]["max"][i].get<double>(), 0.02);
    }
    // Floor and ceiling (7.2 x 7 m) at 2 cm spacing, less what furniture covers.
    EXPECT_GT(floor, 80000);
    EXPECT_GT(ceiling, 110000);
}

TEST(SimDeterminism, SameSeedSameBytesOtherSeedOtherBytes) {
    TempFolder a("det_a"), b("det_b"), c("det_c");
    generate("default", a.str(), 6, 160, 120, true, 7, 1, 0.08);
    generate("default", b.str(), 6, 160, 120, true, 7, 2, 0.08);
    generate("default", c.str(), 6, 160, 120, true, 8, 2, 0.08);
    int files = 0, differing = 0;
    for (const auto& entry : fs::recursive_directory_iterator(a.str())) {
        if (!entry.is_regular_file()) continue;
        const std::string rel = fs::relative(entry.path(), a.str()).string();
        ++files;
        ASSERT_TRUE(fs::exists(b / rel)) << rel;
        EXPECT_EQ(test::read_text(entry.path().string()), test::read_text(b / rel))
            << rel << " differs between two runs with the same seed (1 and 2 threads)";
        if (fs::exists(c / rel) &&
            test::read_text(entry.path().string()) != test::read_text(c / rel))
            ++differing;
    }
    int files_b = 0;
    for (const auto& entry : fs::recursive_directory_iterator(b.str()))
        files_b += entry.is_regular_file();
    EXPECT_EQ(files, files_b);
    EXPECT_GT(files, 6 * 3 + 10);
    EXPECT_GT(differing, 6 * 2) << "another seed changes the images";
    EXPECT_NE(test::read_text(a / "rgb/1.000000.png"), test::read_text(c / "rgb/1.000000.png"));
}

TEST(SimWriter, RefusesAFolderThatIsNotItsOwn) {
    TempFolder t("refuse");
    test::TempFolder other("x");
    { std::ofstream(t / "precious.txt") << "keep me"; }
    PresetOptions o;
    o.frames = 2;
    o.width = 64;
    o.height = 48;
    auto s = make_sequence("default", o);
    ASSERT_TRUE(s.is_ok());
    auto r = write_sequence(*s, t.str());
    EXPECT_FALSE(r.is_ok());
    EXPECT_NE(r.status().message().find("sequence.json"), std::string::npos)
        << r.status().to_string();
    EXPECT_EQ(test::read_text(t / "precious.txt"), "keep me");
    // Its own earlier output is replaced, and other files in it are kept.
    s->static_model_spacing_m = 0.1;
    ASSERT_TRUE(write_sequence(*s, other.str()).is_ok());
    { std::ofstream(other / "notes.txt") << "mine"; }
    s->frames = 1;
    ASSERT_TRUE(write_sequence(*s, other.str()).is_ok());
    EXPECT_FALSE(fs::exists(other / "rgb/1.033333.png")) << "stale frames are removed";
    EXPECT_EQ(test::read_text(other / "notes.txt"), "mine");
}

}  // namespace
}  // namespace df::sim
