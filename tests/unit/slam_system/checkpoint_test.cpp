// SLAM checkpoints: a round trip keeps the map byte for byte and the poses exactly; a corrupt,
// truncated or foreign file is refused naming the file; a system restored mid-sequence tracks
// on from the restored map as the uninterrupted run does, also after frames lost in an outage.
#include "slam_system/checkpoint.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "eval/trajectory_metrics.hpp"
#include "sim_frames.hpp"

namespace df::slam {
namespace {

constexpr int kFrames = 30;

class CheckpointTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               ("df_checkpoint_test_" + std::to_string(getpid()));
        std::filesystem::create_directories(dir_);
        sim::PresetOptions options;
        options.frames = kFrames;
        options.noise = true;
        auto s = sim::make_sequence("static_xyz", options);
        ASSERT_TRUE(s.is_ok()) << s.status().message();
        sequence_ = *s;
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string file(const char* name) const { return (dir_ / name).string(); }

    /// Feeds frames [from, to) to the system; every one must track.
    void feed(SlamSystem& system, int from, int to) {
        for (int i = from; i < to; ++i) {
            const test::SimFrame f = test::render_sim_frame(sequence_, i);
            auto report = system.process(f.image);
            ASSERT_TRUE(report.is_ok()) << report.status().message();
            ASSERT_EQ(report->tracking.state, TrackingState::kOk)
                << "frame " << i << ": " << report->tracking.reason;
        }
    }
    std::vector<io::StampedPose> ground_truth() const {
        std::vector<io::StampedPose> gt;
        for (int i = 0; i < sequence_.frames; ++i) {
            const sim::Iso3 pose = sim::frame_state(sequence_, i).world_T_camera;
            io::StampedPose p;
            p.stamp_s = static_cast<double>(sequence_.stamp_us(i)) * 1e-6;
            p.t = pose.translation();
            p.q = Eigen::Quaterniond(pose.linear());
            gt.push_back(p);
        }
        return gt;
    }

    std::filesystem::path dir_;
    sim::Sequence sequence_;
};

Checkpoint checkpoint_of(const SlamSystem& system) {
    Checkpoint c;
    c.system = system.state();
    c.last_seq = 41;
    c.last_epoch = 1764600000123456789ULL;
    c.last_sensor_ns = 1305031102175304000LL;
    return c;
}

TEST_F(CheckpointTest, RoundTripKeepsTheMapByteForByteAndThePosesExactly) {
    auto system = SlamSystem::create(SystemConfig{});
    ASSERT_TRUE(system.is_ok());
    feed(*system, 0, 8);
    const Checkpoint written = checkpoint_of(*system);
    ASSERT_GT(written.system.surfels.size(), 10000u);
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(write_checkpoint(file("ck.bin"), written).is_ok());
    std::printf(
        "checkpoint of %zu surfels: %.1f MB written in %.1f ms (with fsync)\n",
        written.system.surfels.size(),
        static_cast<double>(std::filesystem::file_size(file("ck.bin"))) / 1e6,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_FALSE(std::filesystem::exists(file("ck.bin.tmp")));
    auto read = read_checkpoint(file("ck.bin"));
    ASSERT_TRUE(read.is_ok()) << read.status().message();
    EXPECT_EQ(read->last_seq, 41u);
    EXPECT_EQ(read->last_epoch, written.last_epoch);
    EXPECT_EQ(read->last_sensor_ns, written.last_sensor_ns);
    const SystemState& a = written.system;
    const SystemState& b = read->system;
    ASSERT_EQ(a.surfels.size(), b.surfels.size());
    static_assert(sizeof(map::Surfel) == 52, "Surfel has no padding to compare");
    EXPECT_EQ(std::memcmp(a.surfels.data(), b.surfels.data(), a.surfels.size() * 52), 0);
    EXPECT_TRUE(a.world_T_camera.matrix() == b.world_T_camera.matrix());
    EXPECT_TRUE(a.last_motion.matrix() == b.last_motion.matrix());
    ASSERT_EQ(a.trajectory.size(), 8u);
    ASSERT_EQ(b.trajectory.size(), 8u);
    for (size_t i = 0; i < a.trajectory.size(); ++i) {
        EXPECT_EQ(a.trajectory[i].stamp_s, b.trajectory[i].stamp_s);
        EXPECT_TRUE(a.trajectory[i].t == b.trajectory[i].t);
        EXPECT_TRUE(a.trajectory[i].q.coeffs() == b.trajectory[i].q.coeffs());
    }
    EXPECT_EQ(a.frames, b.frames);
    EXPECT_EQ(a.map_time, b.map_time);
    EXPECT_EQ(a.input_width, 640);
    EXPECT_EQ(b.input_width, 640);
    EXPECT_EQ(b.input_height, 480);
}

TEST_F(CheckpointTest, AVersion1FileWithoutObjectMapsIsStillRead) {
    auto system = SlamSystem::create(SystemConfig{});
    ASSERT_TRUE(system.is_ok());
    feed(*system, 0, 3);
    const Checkpoint written = checkpoint_of(*system);
    ASSERT_TRUE(written.system.objects.objects.empty());  // static_xyz: no object
    ASSERT_TRUE(write_checkpoint(file("v2.bin"), written).is_ok());
    std::ifstream in(file("v2.bin"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Version 1 is version 2 without the object section at the end of the payload (next id,
    // five counters, a count of 0): cut it, and fix the header's version and length and the hash.
    const size_t header = 8 + 4 + 8, objects = 4 + 5 * 8 + 8;
    ASSERT_GT(bytes.size(), header + objects + 8);
    std::string payload = bytes.substr(header, bytes.size() - header - 8 - objects);
    uint64_t hash = 1469598103934665603ULL;
    for (unsigned char ch : payload) hash = (hash ^ ch) * 1099511628211ULL;
    const uint32_t version = 1;
    const uint64_t length = payload.size();
    std::string v1 = bytes.substr(0, 8);
    v1.append(reinterpret_cast<const char*>(&version), sizeof version);
    v1.append(reinterpret_cast<const char*>(&length), sizeof length);
    v1 += payload;
    v1.append(reinterpret_cast<const char*>(&hash), sizeof hash);
    std::ofstream(file("v1.bin"), std::ios::binary) << v1;
    auto read = read_checkpoint(file("v1.bin"));
    ASSERT_TRUE(read.is_ok()) << read.status().message();
    EXPECT_EQ(read->system.surfels.size(), written.system.surfels.size());
    EXPECT_EQ(read->system.trajectory.size(), 3u);
    EXPECT_TRUE(read->system.objects.objects.empty());
    // A version this build does not know is refused, naming it.
    std::string v9 = bytes;
    v9[8] = 9;
    std::ofstream(file("v9.bin"), std::ios::binary) << v9;
    auto future = read_checkpoint(file("v9.bin"));
    ASSERT_FALSE(future.is_ok());
    EXPECT_NE(future.status().message().find("version 9, this build reads versions 1 to 4"),
              std::string::npos)
        << future.status().message();
}

TEST_F(CheckpointTest, CorruptTruncatedAndForeignFilesAreRefusedNamingTheFile) {
    auto system = SlamSystem::create(SystemConfig{});
    ASSERT_TRUE(system.is_ok());
    feed(*system, 0, 2);
    const std::string good = file("good.bin");
    ASSERT_TRUE(write_checkpoint(good, checkpoint_of(*system)).is_ok());
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto write = [&](const char* name, const std::string& content) {
        std::ofstream(file(name), std::ios::binary) << content;
        return file(name);
    };
    std::string flipped = bytes;
    flipped[flipped.size() / 2] ^= 0x40;
    const std::pair<std::string, std::string> cases[] = {
        {write("flipped.bin", flipped), "hash mismatch"},
        {write("truncated.bin", bytes.substr(0, bytes.size() - 100)), "truncated"},
        {write("empty.bin", ""), "not a SLAM checkpoint"},
        {write("text.bin", "1305031102.175304 0 0 0 0 0 0 1\n"), "not a SLAM checkpoint"},
    };
    for (const auto& [path, why] : cases) {
        auto r = read_checkpoint(path);
        ASSERT_FALSE(r.is_ok()) << path;
        EXPECT_EQ(r.status().code(), StatusCode::kIoError) << path;
        EXPECT_NE(r.status().message().find(path), std::string::npos) << r.status().message();
        EXPECT_NE(r.status().message().find(why), std::string::npos) << r.status().message();
    }
    auto missing = read_checkpoint(file("missing.bin"));
    ASSERT_FALSE(missing.is_ok());
    EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
    // A checkpoint that cannot be written names the file.
    const Status s = write_checkpoint(file("no/such/dir/ck.bin"), checkpoint_of(*system));
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("no/such/dir/ck.bin"), std::string::npos) << s.message();
}

TEST_F(CheckpointTest, ResumedSystemTracksOnLikeTheUninterruptedRun) {
    // Tracking run to 0.01 mm updates (the default stops at 0.1 mm): the resumed run starts from
    // a rendering of the restored map, the uninterrupted one from the model fusion refreshed, and
    // what this test checks is that the checkpoint holds the same map and pose, not how early
    // Gauss-Newton may stop on two renderings of it.
    SystemConfig config;
    config.tracking.min_update_translation_m = 1e-5f;
    config.tracking.min_update_rotation_rad = 1e-5f;
    auto whole = SlamSystem::create(config);
    ASSERT_TRUE(whole.is_ok());
    feed(*whole, 0, kFrames);

    auto first = SlamSystem::create(config);
    ASSERT_TRUE(first.is_ok());
    feed(*first, 0, 15);
    ASSERT_TRUE(write_checkpoint(file("mid.bin"), checkpoint_of(*first)).is_ok());
    first = error(StatusCode::kInternal, "the first process died");

    for (int outage : {0, 3}) {
        auto read = read_checkpoint(file("mid.bin"));
        ASSERT_TRUE(read.is_ok()) << read.status().message();
        auto resumed = SlamSystem::restore(config, std::move(read->system));
        ASSERT_TRUE(resumed.is_ok()) << resumed.status().message();
        EXPECT_EQ(resumed->trajectory().size(), 15u);
        feed(*resumed, 15 + outage, kFrames);
        ASSERT_EQ(resumed->trajectory().size(), static_cast<size_t>(kFrames - outage));
        // Same map, same pose, same model: the uninterrupted run's poses, frame by frame.
        const auto& a = whole->trajectory();
        const auto& b = resumed->trajectory();
        double worst_m = 0;
        for (size_t i = 0; i < b.size(); ++i) {
            const size_t j = i < 15 ? i : i + static_cast<size_t>(outage);
            ASSERT_EQ(a[j].stamp_s, b[i].stamp_s);
            worst_m = std::max(worst_m, (a[j].t - b[i].t).norm());
        }
        std::printf("outage %d frames: largest difference to the uninterrupted run %.3f mm\n",
                    outage, worst_m * 1000);
        EXPECT_LT(worst_m, outage == 0 ? 1e-4 : 3e-3);
        auto ate = eval::compute_ate(ground_truth(), b);
        ASSERT_TRUE(ate.is_ok()) << ate.status().message();
        EXPECT_LT(ate->translation_m.rmse, 0.01);
    }
}

}  // namespace
}  // namespace df::slam
