// Capture's lockstep reader of stage_status checks every answer (dds/sample_check.hpp): a
// hostile answer (timing_count past capacity) for the frame capture waits on is not taken as an
// answer; capture logs one line naming the topic, the writer and the field, waits on, takes the
// good answer that follows, and counts the refused sample in its done line. Over UDP.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <thread>

#include "dds/participant.hpp"
#include "dds/reader.hpp"
#include "dds/writer.hpp"
#include "process.hpp"

namespace df {
namespace {

using Clock = std::chrono::steady_clock;

TEST(CaptureAnswers, AHostileAnswerIsRefusedNamedAndNotTakenForTheStage) {
    test::TempDir dir;
    test::ChildProcess make({test::bin_dir() + "/df_make_sequence", "--preset", "default", "--out",
                             dir.path() + "/seq", "--frames", "3", "--no-models"},
                            dir.path() + "/make.log");
    ASSERT_EQ(make.wait(120), 0) << make.output();
    const std::string ns = test::unique_ns("answers");
    dds::ParticipantConfig pc;
    pc.transport = dds::Transport::kUdp;
    auto participant = dds::Participant::create(pc);
    ASSERT_TRUE(participant) << participant.status().to_string();
    // This test is the lockstep stage "slam": it reads the frames and answers them.
    auto frames = dds::Reader<df_msg_RgbdFrame>::create(*participant,
                                                        dds::topic_name(ns, dds::topics::kFrames));
    ASSERT_TRUE(frames) << frames.status().to_string();
    auto answers = dds::Writer<df_msg_StageStatus>::create(
        *participant, dds::topic_name(ns, dds::topics::kStageStatus));
    ASSERT_TRUE(answers) << answers.status().to_string();

    test::ChildProcess capture(
        {test::bin_dir() + "/df_capture", dir.path() + "/seq", "--set",
         "dds { ns: \"" + ns + "\" transport: \"udp\" }", "--set", "playback: LOCKSTEP", "--set",
         "lockstep_stages: \"slam\"", "--set", "start_wait_s: 60", "--set",
         "lockstep_timeout_s: 60", "--set", "linger_s: 0"},
        dir.path() + "/capture.log");

    auto answer = [&](const df_msg_Header& header, uint32_t timing_count) {
        df_msg_StageStatus s{};
        s.header = header;
        s.header.status = df_msg_FRAME_OK;
        dds::set_name(s.stage, "slam");
        s.timing_count = timing_count;
        ASSERT_TRUE(answers->write_copy(s));
    };
    // Frames as they come: (seq, header).
    std::optional<df_msg_Header> got[3];
    auto take = [&]() {
        (void)frames->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            if (f.header.seq < 3) got[f.header.seq] = f.header;
        });
    };
    auto wait_frame = [&](uint64_t seq, double seconds) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end && !got[seq]) {
            take();
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return got[seq].has_value();
    };

    ASSERT_TRUE(wait_frame(0, 60)) << capture.output();
    answer(*got[0], 1000);  // MAX_STAGE_TIMINGS is far smaller
    // Taken for an answer, it would release frame 1 within milliseconds.
    EXPECT_FALSE(wait_frame(1, 1.5)) << "frame 1 came after a hostile answer only";
    answer(*got[0], 0);
    ASSERT_TRUE(wait_frame(1, 30)) << "the good answer did not release frame 1:\n"
                                   << capture.output();
    answer(*got[1], 0);
    ASSERT_TRUE(wait_frame(2, 30)) << capture.output();
    answer(*got[2], 0);
    ASSERT_EQ(capture.wait(60), 0) << capture.output();

    const std::string log = capture.output();
    EXPECT_NE(log.find(dds::topic_name(ns, dds::topics::kStageStatus)), std::string::npos) << log;
    EXPECT_NE(log.find("timing_count 1000"), std::string::npos) << log;
    EXPECT_NE(log.find("writer "), std::string::npos) << log;
    EXPECT_NE(log.find("done: 3 frames published"), std::string::npos) << log;
    EXPECT_NE(log.find("1 stage_status samples refused"), std::string::npos) << log;
    EXPECT_NE(log.find("0 lockstep timeouts"), std::string::npos) << log;
}

}  // namespace
}  // namespace df
