// The DDS layer over shared memory (needs the RouDi fixture): loans come from iceoryx, unwritten
// loans go back to the pool, an exhausted pool falls back to copies instead of crashing, and a
// loaned frame reaches a reader in another participant byte for byte.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "process.hpp"

namespace df::dds {
namespace {

using test::shm_participant;

TEST(SharedMemory, UnwrittenLoansReturnToThePool) {
    ASSERT_TRUE(test::roudi_available());
    Participant p = shm_participant();
    auto w = Writer<df_msg_RgbdFrame>::create(p, test::unique_ns("ret") + "/frames");
    ASSERT_TRUE(w.is_ok());
    ASSERT_TRUE(w->loans_shared_memory());
    // 20 x 8 loans from a pool of 64 chunks: only possible if dropped loans are returned.
    for (int round = 0; round < 20; ++round) {
        std::vector<Loan<df_msg_RgbdFrame>> held;
        for (int i = 0; i < kMaxOpenLoans; ++i) {
            auto l = w->loan();
            ASSERT_TRUE(l.is_ok());
            EXPECT_TRUE(l->shared_memory());
            held.push_back(std::move(*l));
        }
    }
    EXPECT_EQ(w->loan_failures(), 0U);
}

TEST(SharedMemory, MoreOpenLoansThanCycloneTracksFallBackToTheHeap) {
    ASSERT_TRUE(test::roudi_available());
    Participant p = shm_participant();
    auto w = Writer<df_msg_RgbdFrame>::create(p, test::unique_ns("open") + "/frames");
    ASSERT_TRUE(w.is_ok() && w->loans_shared_memory());
    std::vector<Loan<df_msg_RgbdFrame>> held;
    for (int i = 0; i < kMaxOpenLoans; ++i) held.push_back(std::move(*w->loan()));
    auto extra = w->loan();
    ASSERT_TRUE(extra.is_ok());
    EXPECT_FALSE(extra->shared_memory());
    held.pop_back();
    auto again = w->loan();
    ASSERT_TRUE(again.is_ok());
    EXPECT_TRUE(again->shared_memory());
}

TEST(SharedMemory, ExhaustedPoolGivesErrorValuesThenRecovers) {
    ASSERT_TRUE(test::roudi_available());
    Participant p = shm_participant();
    const std::string ns = test::unique_ns("exhaust");
    // Ten writers holding 8 loans each ask for 80 chunks of a pool of 64.
    std::vector<Writer<df_msg_RgbdFrame>> writers;
    for (int i = 0; i < 10; ++i) {
        auto w = Writer<df_msg_RgbdFrame>::create(p, ns + "/frames" + std::to_string(i));
        ASSERT_TRUE(w.is_ok());
        writers.push_back(std::move(*w));
    }
    auto r = Reader<df_msg_RgbdFrame>::create(p, ns + "/frames9", {QosProfile::kFrames, 4});
    auto ws = WaitSet::create(p);
    ASSERT_TRUE(r.is_ok() && ws.is_ok() && ws->attach_reader(r->get()).is_ok());
    std::vector<Loan<df_msg_RgbdFrame>> hoard;
    int fallbacks = 0;
    for (auto& w : writers) {
        for (int i = 0; i < kMaxOpenLoans; ++i) {
            auto l = w.loan();
            ASSERT_TRUE(l.is_ok());
            if (l->shared_memory())
                hoard.push_back(std::move(*l));
            else
                ++fallbacks;
        }
    }
    EXPECT_GE(fallbacks, 1) << "the pool never ran out";
    // With the pool empty even a copied write has no chunk: an error value, not an abort.
    auto l = writers.back().loan();
    ASSERT_TRUE(l.is_ok());
    EXPECT_FALSE(l->shared_memory());
    (*l)->width = 2;
    (*l)->height = 1;
    EXPECT_FALSE(writers.back().write(std::move(*l)).is_ok());
    hoard.clear();  // back to the pool: loaning and writing work again
    auto again = writers.back().loan();
    ASSERT_TRUE(again.is_ok());
    EXPECT_TRUE(again->shared_memory()) << "chunks were not returned";
    (*again)->header.seq = 4242;
    EXPECT_TRUE(writers.back().write(std::move(*again)).is_ok());
    int got = 0;
    for (int tries = 0; tries < 30 && got == 0; ++tries) {
        (void)ws->wait(DDS_MSECS(100));
        (void)r->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            got += f.header.seq == 4242;
        });
    }
    EXPECT_EQ(got, 1);
}

TEST(SharedMemory, LoanedFrameReachesAnotherParticipantIntact) {
    ASSERT_TRUE(test::roudi_available());
    Participant p = shm_participant();
    const std::string topic = test::unique_ns("loan") + "/frames";
    auto r = Reader<df_msg_RgbdFrame>::create(p, topic, {QosProfile::kFrames, 4});
    auto w = Writer<df_msg_RgbdFrame>::create(p, topic);
    auto ws = WaitSet::create(p);
    ASSERT_TRUE(r.is_ok() && w.is_ok() && ws.is_ok() && ws->attach_reader(r->get()).is_ok());
    auto l = w->loan();
    ASSERT_TRUE(l.is_ok() && l->shared_memory());
    (*l)->header.seq = 77;
    (*l)->width = 640;
    (*l)->height = 480;
    for (size_t i = 0; i < sizeof((*l)->rgb); ++i) (*l)->rgb[i] = static_cast<uint8_t>(i * 31);
    for (size_t i = 0; i < 640 * 480; ++i) (*l)->depth[i] = static_cast<uint16_t>(i * 7);
    ASSERT_TRUE(w->write(std::move(*l)).is_ok());
    int got = 0;
    for (int tries = 0; tries < 30 && got == 0; ++tries) {
        (void)ws->wait(DDS_MSECS(100));
        (void)r->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            ++got;
            EXPECT_EQ(f.header.seq, 77U);
            bool same = true;
            for (size_t i = 0; i < sizeof(f.rgb) && same; ++i)
                same = f.rgb[i] == static_cast<uint8_t>(i * 31);
            for (size_t i = 0; i < 640 * 480 && same; ++i)
                same = f.depth[i] == static_cast<uint16_t>(i * 7);
            EXPECT_TRUE(same);
        });
    }
    EXPECT_EQ(got, 1);
}

}  // namespace
}  // namespace df::dds
