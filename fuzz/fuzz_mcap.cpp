// The MCAP reader (df_tap play, df_eval) on any file: open() checks the structure, then every
// message is visited. Property: no crash, no read outside the file or a loaded chunk; each
// message names a known channel and its data can be read to its last byte.
#include "fuzz_util.hpp"
#include "mcap/mcap_reader.hpp"

using namespace df;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::as_file("mcap", data, size, ".mcap");
    auto reader = mcap::Reader::open(path);
    if (!reader) return 0;
    const auto& channels = (*reader)->channels();
    (void)(*reader)->for_each_message([&](const mcap::Message& m) {
        DF_FUZZ_CHECK(channels.count(m.channel_id) == 1);
        // Touch the bytes: ASan reports a read outside the loaded chunk.
        volatile uint8_t sink = 0;
        for (size_t i = 0; i < m.size; i += 64) sink = sink ^ m.data[i];
        if (m.size > 0) sink = sink ^ m.data[m.size - 1];
        (void)sink;
        return true;
    });
    return 0;
}
