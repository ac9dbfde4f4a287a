// Topic samples as a hostile writer could send them, both ways they reach a consumer: as CDR
// bytes deserialized by Cyclone (from the network, or `df_tap play` from an MCAP file), and as
// raw struct bytes (a shared-memory chunk is read in place). Then check_sample(), and for the
// samples it accepts, the converters: they must stay inside the sample's buffers.
#include <cstring>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "dds/cdr.hpp"
#include "dds/msg_convert.hpp"
#include "dds/msg_types.hpp"
#include "dds/sample_check.hpp"
#include "fuzz_util.hpp"

namespace {

using namespace df;

/// Uses an accepted sample as the consumers do.
void consume(const dds::TypeInfo& type, const void* sample) {
    const dds_topic_descriptor_t* d = type.descriptor;
    if (d == dds::MsgTraits<df_msg_RgbdFrame>::descriptor()) {
        const auto& f = *static_cast<const df_msg_RgbdFrame*>(sample);
        auto image = dds::to_image(f);
        DF_FUZZ_CHECK(image.is_ok());
        DF_FUZZ_CHECK(image->rgb.cols == f.width && image->rgb.rows == f.height);
        DF_FUZZ_CHECK(image->depth.cols == f.width && image->depth.rows == f.height);
    } else if (d == dds::MsgTraits<df_msg_GeometricSegments>::descriptor()) {
        const auto& g = *static_cast<const df_msg_GeometricSegments*>(sample);
        auto c = dds::checked(g);
        DF_FUZZ_CHECK(c.is_ok());
        const cv::Mat labels = dds::labels_of(*c);
        double hi = 0;
        if (!labels.empty()) cv::minMaxLoc(labels, nullptr, &hi);
        DF_FUZZ_CHECK(hi <= g.segment_count);
    } else if (d == dds::MsgTraits<df_msg_CompressedImage>::descriptor()) {
        const auto& m = *static_cast<const df_msg_CompressedImage*>(sample);
        if (m.data._length == 0) return;
        // The detector's decode: whatever it returns, an accepted sample announces a size within
        // the capacity, so decoding cannot be a memory bomb.
        try {
            const cv::Mat bytes(1, static_cast<int>(m.data._length), CV_8UC1, m.data._buffer);
            (void)cv::imdecode(bytes, cv::IMREAD_COLOR);
        } catch (const cv::Exception&) {
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const auto& types = dds::all_types();
    const dds::TypeInfo& type = types[(data[0] & 0x7f) % types.size()];
    const bool as_cdr = (data[0] & 0x80) != 0;
    ++data;
    --size;
    const size_t n = type.descriptor->m_size;
    std::vector<uint8_t> storage(n, 0);
    void* sample = storage.data();
    if (as_cdr) {
        if (!dds::from_cdr(type.descriptor, data, size, sample).is_ok()) {
            dds_sample_free(sample, type.descriptor, DDS_FREE_CONTENTS);
            return 0;
        }
    } else {
        // Raw chunk bytes; pointers (the CompressedImage sequence) cannot come from a chunk.
        std::memcpy(sample, data, std::min(n, size));
        if (type.descriptor == dds::MsgTraits<df_msg_CompressedImage>::descriptor()) {
            auto* c = static_cast<df_msg_CompressedImage*>(sample);
            c->data._buffer = nullptr;
            c->data._length = c->data._maximum = 0;
            c->data._release = false;
        }
    }
    if (dds::check_sample(type, sample).is_ok()) consume(type, sample);
    if (as_cdr) dds_sample_free(sample, type.descriptor, DDS_FREE_CONTENTS);
    return 0;
}
