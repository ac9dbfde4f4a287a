// df_tap play of a recording with corrupt samples (generated here): a frame whose width is past
// its buffers and a pose with a NaN translation are each refused with a line naming the file,
// the message and the field, and never published; the good messages around them arrive intact;
// play exits 1 saying how many it refused. A file of many corrupt samples logs 20 lines and
// counts the rest. Over UDP (no RouDi needed).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include "dds/cdr.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "df_msgs_idl_text.hpp"
#include "mcap/mcap_writer.hpp"
#include "process.hpp"

namespace df {
namespace {

constexpr uint32_t kDomain = 23;

std::unique_ptr<df_msg_RgbdFrame> frame(uint64_t seq, uint16_t width) {
    auto f = std::make_unique<df_msg_RgbdFrame>();
    std::memset(f.get(), 0, sizeof *f);
    f->header.seq = seq;
    f->width = width;
    f->height = 2;
    f->intrinsics = {500.f, 500.f, 2.f, 1.f};
    f->depth_units_per_m = 5000;
    f->depth[5] = static_cast<uint16_t>(1000 + seq);
    return f;
}

df_msg_CameraPose pose(uint64_t seq, double ty) {
    df_msg_CameraPose p{};
    p.header.seq = seq;
    p.world_T_camera.qw = 1;
    p.world_T_camera.ty = ty;
    return p;
}

/// Writes run.mcap: frames 0, 1 (width 1000: corrupt), 2 on <ns>/frames and poses 0 (NaN ty:
/// corrupt), 1 on <ns>/camera_pose; messages 0..4 in log-time order f0 f1 p0 f2 p1.
void write_recording(const std::string& path, const std::string& ns) {
    auto w = mcap::Writer::open(path);
    ASSERT_TRUE(w) << w.status().to_string();
    auto fs = (*w)->add_schema("df::msg::RgbdFrame", "omgidl", msg::kIdlText);
    auto ps = (*w)->add_schema("df::msg::CameraPose", "omgidl", msg::kIdlText);
    ASSERT_TRUE(fs && ps);
    auto fc = (*w)->add_channel(*fs, ns + "/frames", "cdr");
    auto pc = (*w)->add_channel(*ps, ns + "/camera_pose", "cdr");
    ASSERT_TRUE(fc && pc);
    auto put_frame = [&](uint64_t seq, uint16_t width, uint64_t t) {
        const auto f = frame(seq, width);
        const auto cdr = dds::to_cdr(&df_msg_RgbdFrame_desc, f.get());
        ASSERT_TRUE((*w)->write(*fc, static_cast<uint32_t>(seq), t, t, cdr.data(), cdr.size()));
    };
    auto put_pose = [&](uint64_t seq, double ty, uint64_t t) {
        const auto p = pose(seq, ty);
        const auto cdr = dds::to_cdr(&df_msg_CameraPose_desc, &p);
        ASSERT_TRUE((*w)->write(*pc, static_cast<uint32_t>(seq), t, t, cdr.data(), cdr.size()));
    };
    put_frame(0, 4, 1000);
    put_frame(1, 1000, 2000);
    put_pose(0, std::nan(""), 2500);
    put_frame(2, 4, 3000);
    put_pose(1, 0.5, 3500);
    ASSERT_TRUE((*w)->close());
}

TEST(TapPlayCheck, CorruptSamplesAreRefusedNamedAndNeverPublished) {
    test::TempDir dir;
    const std::string ns = test::unique_ns("tap_play_check");
    const std::string file = dir.path() + "/run.mcap";
    write_recording(file, ns);
    if (HasFatalFailure()) return;

    dds::ParticipantConfig pc;
    pc.domain_id = kDomain;
    pc.transport = dds::Transport::kUdp;
    auto p = dds::Participant::create(pc);
    ASSERT_TRUE(p) << p.status().to_string();
    auto frames =
        dds::Reader<df_msg_RgbdFrame>::create(*p, ns + "/frames", {dds::QosProfile::kFrames, 16});
    auto poses = dds::Reader<df_msg_CameraPose>::create(*p, ns + "/camera_pose");
    ASSERT_TRUE(frames && poses);
    auto ws = dds::WaitSet::create(*p);
    ASSERT_TRUE(ws);
    ASSERT_TRUE(ws->attach_reader(frames->get()));
    ASSERT_TRUE(ws->attach_reader(poses->get()));

    test::ChildProcess play(
        {test::bin_dir() + "/df_tap", "--transport", "udp", "--domain", std::to_string(kDomain),
         "play", file, "--rate", "0", "--wait-readers", "1", "--start-wait", "30"},
        dir.path() + "/play.log");
    std::set<uint64_t> frame_seqs, pose_seqs;
    bool intact = true;
    auto drain = [&] {
        (void)frames->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            frame_seqs.insert(f.header.seq);
            intact = intact && f.width == 4 && f.depth[5] == 1000 + f.header.seq;
        });
        (void)poses->take([&](const df_msg_CameraPose& c, const dds_sample_info_t&) {
            pose_seqs.insert(c.header.seq);
            intact = intact && c.world_T_camera.ty == 0.5;
        });
    };
    // Until play has exited and everything it wrote is in (it waits for acknowledgements).
    for (int i = 0; i < 1200 && (play.running() || frame_seqs.size() + pose_seqs.size() < 3); ++i) {
        (void)ws->wait(DDS_MSECS(50));
        drain();
    }
    const int rc = play.wait(30);
    drain();
    const std::string log = play.output();
    EXPECT_EQ(rc, 1) << log;
    EXPECT_EQ(frame_seqs, (std::set<uint64_t>{0, 2})) << log;
    EXPECT_EQ(pose_seqs, (std::set<uint64_t>{1})) << log;
    EXPECT_TRUE(intact) << "a published sample differs from the recorded one";
    EXPECT_NE(log.find(file + ": message 1 (topic '" + ns +
                       "/frames', sequence 1, log time 2000 ns): RgbdFrame.width 1000 > "
                       "MAX_WIDTH 640; not published"),
              std::string::npos)
        << log;
    EXPECT_NE(log.find(file + ": message 2 (topic '" + ns +
                       "/camera_pose', sequence 0, log time 2500 ns): "
                       "CameraPose.world_T_camera.ty nan not in"),
              std::string::npos)
        << log;
    EXPECT_NE(log.find(file + ": 2 message(s) failed their check and were not published; "
                              "played 3"),
              std::string::npos)
        << log;
}

TEST(TapPlayCheck, AFileOfCorruptSamplesLogsTwentyLinesCountsTheRestAndPlaysTheGoodOne) {
    test::TempDir dir;
    const std::string ns = test::unique_ns("tap_play_flood");
    const std::string file = dir.path() + "/flood.mcap";
    {
        auto w = mcap::Writer::open(file);
        ASSERT_TRUE(w) << w.status().to_string();
        auto schema = (*w)->add_schema("df::msg::CameraPose", "omgidl", msg::kIdlText);
        ASSERT_TRUE(schema);
        auto channel = (*w)->add_channel(*schema, ns + "/camera_pose", "cdr");
        ASSERT_TRUE(channel);
        for (uint64_t seq = 0; seq <= 30; ++seq) {  // 30 corrupt poses, then a good one
            const auto pz = pose(seq, seq < 30 ? 1e300 : 0.5);
            const auto cdr = dds::to_cdr(&df_msg_CameraPose_desc, &pz);
            ASSERT_TRUE((*w)->write(*channel, static_cast<uint32_t>(seq), 1000 + seq, 1000 + seq,
                                    cdr.data(), cdr.size()));
        }
        ASSERT_TRUE((*w)->close());
    }
    dds::ParticipantConfig pc;
    pc.domain_id = kDomain;
    pc.transport = dds::Transport::kUdp;
    auto p = dds::Participant::create(pc);
    ASSERT_TRUE(p) << p.status().to_string();
    auto poses = dds::Reader<df_msg_CameraPose>::create(*p, ns + "/camera_pose");
    ASSERT_TRUE(poses);
    test::ChildProcess play(
        {test::bin_dir() + "/df_tap", "--transport", "udp", "--domain", std::to_string(kDomain),
         "play", file, "--rate", "0", "--wait-readers", "1", "--start-wait", "30"},
        dir.path() + "/play.log");
    std::set<uint64_t> seqs;
    auto drain = [&] {
        (void)poses->take([&](const df_msg_CameraPose& c, const dds_sample_info_t&) {
            seqs.insert(c.header.seq);
        });
    };
    for (int i = 0; i < 600 && (play.running() || seqs.empty()); ++i) {
        drain();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_EQ(play.wait(30), 1) << play.output();
    drain();
    const std::string log = play.output();
    EXPECT_EQ(seqs, (std::set<uint64_t>{30})) << log;
    size_t lines = 0;
    for (size_t at = log.find("; not published"); at != std::string::npos;
         at = log.find("; not published", at + 1))
        ++lines;
    EXPECT_EQ(lines, 20U) << log;
    EXPECT_NE(log.find("message 19 (topic '" + ns + "/camera_pose', sequence 19"),
              std::string::npos)
        << log;
    EXPECT_EQ(log.find("message 20 (topic"), std::string::npos) << log;
    EXPECT_NE(log.find("further corrupt messages are counted, not logged"), std::string::npos)
        << log;
    EXPECT_NE(log.find("30 message(s) failed their check and were not published; played 1"),
              std::string::npos)
        << log;
}

}  // namespace
}  // namespace df
