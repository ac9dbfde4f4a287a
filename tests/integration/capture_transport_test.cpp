// Capture -> subscriber in another process, over shared memory and over UDP: every frame's bytes
// arrive intact and, in lockstep, none is lost; a corrupt PNG costs one frame and one error line.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <random>

#include "dds/msg_convert.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "io/tum/tum_folder.hpp"
#include "process.hpp"

namespace df {
namespace {

std::vector<io::RgbdImage> make_frames(int n, int w, int h) {
    std::mt19937 rng(42);
    std::vector<io::RgbdImage> frames;
    for (int i = 0; i < n; ++i) {
        io::RgbdImage f;
        f.rgb = cv::Mat(h, w, CV_8UC3);
        f.depth = cv::Mat(h, w, CV_16UC1);
        cv::randu(f.rgb, 0, 256);
        cv::randu(f.depth, 0, 20000);
        f.sensor_ns = 1'000'000'000LL + i * 33'333'000LL;  // whole microseconds, as TUM lists hold
        frames.push_back(f);
    }
    return frames;
}

size_t count_lines_with(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1))
        ++n;
    return n;
}

struct Received {
    std::vector<uint64_t> seqs;
    int intact = 0;
};

/// Subscribes in this process, acknowledges each frame as stage "test", compares bytes.
Received receive(dds::Participant& p, const std::string& ns,
                 const std::vector<io::RgbdImage>& expected, const std::vector<int>& expected_index,
                 test::ChildProcess& capture) {
    Received got;
    auto reader = dds::Reader<df_msg_RgbdFrame>::create(p, dds::topic_name(ns, "frames"),
                                                        {dds::QosProfile::kFrames, 64});
    auto acks = dds::Writer<df_msg_StageStatus>::create(p, dds::topic_name(ns, "stage_status"));
    auto ws = dds::WaitSet::create(p);
    if (!reader || !acks || !ws || !ws->attach_reader(reader->get())) {
        ADD_FAILURE() << "DDS set-up failed";
        return got;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    while (got.seqs.size() < expected_index.size() && std::chrono::steady_clock::now() < deadline) {
        (void)ws->wait(DDS_MSECS(100));
        (void)reader->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            const size_t k = got.seqs.size();
            got.seqs.push_back(f.header.seq);
            if (k < expected_index.size()) {
                const io::RgbdImage& e = expected[static_cast<size_t>(expected_index[k])];
                const auto c = dds::checked(f);
                ASSERT_TRUE(c) << c.status().to_string();
                const cv::Mat rgb = dds::rgb_view(*c), depth = dds::depth_view(*c);
                const bool same = f.width == e.rgb.cols && f.height == e.rgb.rows &&
                                  cv::norm(rgb, e.rgb, cv::NORM_INF) == 0 &&
                                  cv::norm(depth, e.depth, cv::NORM_INF) == 0 &&
                                  f.header.sensor_ns == static_cast<uint64_t>(e.sensor_ns);
                got.intact += same ? 1 : 0;
            }
            df_msg_StageStatus a{};
            a.header = f.header;
            dds::set_name(a.stage, "test");
            (void)acks->write_copy(a);
        });
        if (!capture.running() && got.seqs.size() < expected_index.size()) {
            (void)ws->wait(DDS_MSECS(200));  // drain what is in flight, then give up
            (void)reader->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
                got.seqs.push_back(f.header.seq);
            });
            break;
        }
    }
    return got;
}

std::vector<std::string> capture_args(const std::string& folder, const std::string& ns,
                                      const std::string& transport, int domain) {
    return {test::bin_dir() + "/df_capture",
            folder,
            "--set",
            "dds { ns: \"" + ns + "\" transport: \"" + transport +
                "\" domain_id: " + std::to_string(domain) + " }",
            "--set",
            "playback: LOCKSTEP",
            "--set",
            "lockstep_stages: \"test\"",
            "--set",
            "start_wait_s: 30",
            "--set",
            "lockstep_timeout_s: 20",
            "--set",  // principal point inside both the 640x480 and the 320x240 test images
            "cx: 160 cy: 120"};
}

class CaptureTransport : public ::testing::TestWithParam<std::string> {};

TEST_P(CaptureTransport, EveryFrameArrivesIntactAndNoneIsLostInLockstep) {
    const std::string transport = GetParam();
    test::TempDir dir;
    ASSERT_TRUE(test::roudi_available()) << "no RouDi: run through ctest (fixture roudi)";
    const auto frames = make_frames(24, 640, 480);
    ASSERT_TRUE(io::write_tum_folder(dir.path() + "/seq", frames).is_ok());
    const int domain = transport == "shm" ? 0 : 7;
    dds::ParticipantConfig pc;
    pc.domain_id = static_cast<uint32_t>(domain);
    pc.transport = transport == "shm" ? dds::Transport::kSharedMemory : dds::Transport::kUdp;
    auto p = dds::Participant::create(pc);
    ASSERT_TRUE(p.is_ok()) << p.status().to_string();
    const std::string ns = test::unique_ns("transport_" + transport);
    test::ChildProcess capture(capture_args(dir.path() + "/seq", ns, transport, domain),
                               dir.path() + "/capture.log");
    std::vector<int> index(frames.size());
    for (size_t i = 0; i < index.size(); ++i) index[i] = static_cast<int>(i);
    const Received got = receive(*p, ns, frames, index, capture);
    EXPECT_EQ(capture.wait(30), 0) << capture.output();
    ASSERT_EQ(got.seqs.size(), frames.size()) << capture.output();
    for (size_t i = 0; i < got.seqs.size(); ++i) EXPECT_EQ(got.seqs[i], i);
    EXPECT_EQ(got.intact, static_cast<int>(frames.size()));
    const std::string log = capture.output();
    if (transport == "shm") {
        EXPECT_NE(log.find("frames (df::msg::RgbdFrame, qos frames): shared memory, loaned"),
                  std::string::npos)
            << log;
    } else {
        EXPECT_NE(log.find("frames (df::msg::RgbdFrame, qos frames): network (UDP)"),
                  std::string::npos)
            << log;
    }
}

INSTANTIATE_TEST_SUITE_P(Transports, CaptureTransport, ::testing::Values("shm", "udp"));

TEST(CaptureBadInput, CorruptPngCostsOneFrameAndOneErrorLine) {
    test::TempDir dir;
    ASSERT_TRUE(test::roudi_available()) << "no RouDi: run through ctest (fixture roudi)";
    const auto frames = make_frames(10, 320, 240);
    const std::string seq = dir.path() + "/seq";
    ASSERT_TRUE(io::write_tum_folder(seq, frames).is_ok());
    io::TumFolderConfig tc;
    tc.folder = seq;
    tc.intrinsics = {535.4, 539.2, 160.0, 120.0};  // fits the 320x240 images
    auto source = io::TumFolderSource::open(tc);
    ASSERT_TRUE(source.is_ok());
    const std::string bad = seq + "/" + (*source)->pairs()[4].rgb.path;
    { std::ofstream(bad, std::ios::trunc) << "this is not a PNG"; }

    dds::Participant p = test::shm_participant();
    const std::string ns = test::unique_ns("corrupt");
    test::ChildProcess capture(capture_args(seq, ns, "shm", 0), dir.path() + "/capture.log");
    const std::vector<int> index = {0, 1, 2, 3, 5, 6, 7, 8, 9};
    const Received got = receive(p, ns, frames, index, capture);
    EXPECT_EQ(capture.wait(30), 0);
    EXPECT_EQ(got.seqs.size(), index.size());
    EXPECT_EQ(got.intact, static_cast<int>(index.size()));
    const std::string log = capture.output();
    EXPECT_EQ(count_lines_with(log, "[error]"), 1U) << log;
    EXPECT_NE(log.find(bad), std::string::npos) << "the error must name the file\n" << log;
    EXPECT_NE(log.find("1 bad frames skipped"), std::string::npos) << log;
}

TEST(CaptureOpenNi, VirtualCameraFramesArriveIntact) {
    // The live-camera path, without hardware: df_capture opens the project's OpenNI2 driver that
    // serves a recorded folder as a device (df-virtual://), found through df_capture's RUNPATH.
    test::TempDir dir;
    ASSERT_TRUE(test::roudi_available()) << "no RouDi: run through ctest (fixture roudi)";
    auto frames = make_frames(12, 640, 480);
    for (auto& f : frames) cv::randu(f.depth, 0, 5000 * 6);  // TUM units; the camera gives mm
    ASSERT_TRUE(io::write_tum_folder(dir.path() + "/seq", frames).is_ok());
    std::vector<io::RgbdImage> expected = frames;
    for (auto& e : expected) {
        cv::Mat mm;
        e.depth.convertTo(mm, CV_16UC1, 1000.0 / 5000.0);  // rounds to nearest, as the driver does
        e.depth = mm;
    }
    dds::Participant p = test::shm_participant();
    const std::string ns = test::unique_ns("openni");
    auto args = capture_args("", ns, "shm", 0);
    args.erase(args.begin() + 1);  // no folder
    args.insert(args.end(), {"--set", "source: OPENNI", "--set",
                             "openni_uri: \"df-virtual://" + dir.path() + "/seq\""});
    test::ChildProcess capture(args, dir.path() + "/capture.log", {"DF_VIRTUAL_CAMERA_LOCKSTEP=1"});
    std::vector<int> index(frames.size());
    for (size_t i = 0; i < index.size(); ++i) index[i] = static_cast<int>(i);
    // Stamps: the device clock is the sequence's, in microseconds (same as written).
    const Received got = receive(p, ns, expected, index, capture);
    capture.kill(SIGINT);  // a camera never ends by itself: stop it like a user would
    EXPECT_EQ(capture.wait(20), 0) << capture.output();
    ASSERT_EQ(got.seqs.size(), frames.size()) << capture.output();
    EXPECT_EQ(got.intact, static_cast<int>(frames.size())) << capture.output();
}

TEST(CaptureBadInput, MalformedListLineIsNamedAndTheRunGoesOn) {
    test::TempDir dir;
    ASSERT_TRUE(test::roudi_available()) << "no RouDi: run through ctest (fixture roudi)";
    const auto frames = make_frames(6, 320, 240);
    const std::string seq = dir.path() + "/seq";
    ASSERT_TRUE(io::write_tum_folder(seq, frames).is_ok());
    {
        std::ofstream(seq + "/associations.txt", std::ios::app)
            << "1.5 rgb/x.png not-a-stamp depth/x.png\n";
    }
    dds::Participant p = test::shm_participant();
    const std::string ns = test::unique_ns("badline");
    test::ChildProcess capture(capture_args(seq, ns, "shm", 0), dir.path() + "/capture.log");
    const std::vector<int> index = {0, 1, 2, 3, 4, 5};
    const Received got = receive(p, ns, frames, index, capture);
    EXPECT_EQ(capture.wait(30), 0);
    EXPECT_EQ(got.intact, 6);
    const std::string log = capture.output();
    EXPECT_EQ(count_lines_with(log, "[error]"), 1U) << log;
    EXPECT_NE(log.find("associations.txt:7"), std::string::npos)
        << "the error must name file and line\n"
        << log;
}

TEST(CaptureBadInput, UnreadableFolderFailsAtStartWithAClearMessage) {
    test::TempDir dir;
    test::ChildProcess capture({test::bin_dir() + "/df_capture", dir.path() + "/does-not-exist"},
                               dir.path() + "/capture.log");
    EXPECT_EQ(capture.wait(20), 1);
    const std::string log = capture.output();
    EXPECT_NE(log.find("cannot open the input"), std::string::npos) << log;
    EXPECT_NE(log.find(dir.path() + "/does-not-exist"), std::string::npos) << log;
}

TEST(CaptureBadInput, BadConfigurationNamesTheField) {
    test::TempDir dir;
    test::ChildProcess capture({test::bin_dir() + "/df_capture", "--set", "playbak: LOCKSTEP"},
                               dir.path() + "/capture.log");
    EXPECT_EQ(capture.wait(20), 2);
    EXPECT_NE(capture.output().find("playbak"), std::string::npos) << capture.output();
}

}  // namespace
}  // namespace df
