// tap echo's text: every type's header shows the run epoch next to the sequence number, so two
// frames of the same seq from two capture runs (a restart) can be told apart on screen.
#include "print.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace df::tap {
namespace {

TEST(TapPrint, EveryTypesHeaderShowsTheRunEpoch) {
    ASSERT_FALSE(dds::all_types().empty());
    for (const dds::TypeInfo& type : dds::all_types()) {
        // A zeroed sample is valid to print for every type (empty arrays and sequences).
        std::vector<unsigned char> sample(type.descriptor->m_size, 0);
        df_msg_Header header{};
        header.capture_ns = 1764600000111111111ULL;
        header.seq = 42;
        header.epoch = 1764599999123456789ULL;
        header.source_id = 3;
        std::memcpy(sample.data(), &header, sizeof header);  // every type starts with Header
        const std::string text = print_sample(type, sample.data());
        EXPECT_NE(text.find("  seq: 42\n  epoch: 1764599999123456789\n  source_id: 3\n"),
                  std::string::npos)
            << type.name << ":\n"
            << text;
    }
}

TEST(TapPrint, EpochIsPrintedInFullAt64Bits) {
    const dds::TypeInfo* type = dds::find_type("df::msg::CameraPose");
    ASSERT_NE(type, nullptr);
    df_msg_CameraPose pose{};
    pose.header.epoch = 18446744073709551615ULL;  // no narrowing to 32 bits or a double
    const std::string text = print_sample(*type, &pose);
    EXPECT_NE(text.find("  epoch: 18446744073709551615\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace df::tap
