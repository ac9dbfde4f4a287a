#include "dds/reader.hpp"

#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_shm_transport.h>

#include <cstring>
#include <vector>

#include "dds/dds_error.hpp"

namespace df::dds {
namespace {

constexpr int kMaxBatch = 64;

/// A zeroed, suitably aligned buffer for one deserialized sample.
struct Scratch {
    explicit Scratch(size_t size) : bytes((size + 15) / 16) {}
    void* get() { return bytes.data(); }
    void clear() { std::memset(bytes.data(), 0, bytes.size() * 16); }
    struct alignas(16) Block {
        unsigned char b[16];
    };
    std::vector<Block> bytes;
};

/// The index of the last sample with valid data, or -1.
int last_valid(const dds_sample_info_t* infos, int n) {
    for (int i = n - 1; i >= 0; --i)
        if (infos[i].valid_data) return i;
    return -1;
}

Result<int> take_zero_copy(dds_entity_t reader, const dds_topic_descriptor_t* desc, int max,
                           const BatchVisitor& visit) {
    ddsi_serdata* data[kMaxBatch] = {};
    dds_sample_info_t infos[kMaxBatch];
    const int n = dds_takecdr(reader, data, static_cast<uint32_t>(max), infos, DDS_ANY_STATE);
    if (n < 0) return check(n, "taking samples");
    const int newest = last_valid(infos, n);
    int visited = 0;
    std::unique_ptr<Scratch> scratch;
    for (int i = 0; i < n; ++i) {
        if (infos[i].valid_data) {
            void* chunk = data[i]->iox_chunk;
            if (chunk != nullptr && shm_get_data_state(chunk) == IOX_CHUNK_CONTAINS_RAW_DATA) {
                visit(chunk, infos[i], i == newest);  // the sample itself, in shared memory
            } else {
                if (!scratch) scratch = std::make_unique<Scratch>(desc->m_size);
                scratch->clear();
                if (ddsi_serdata_to_sample(data[i], scratch->get(), nullptr, nullptr)) {
                    visit(scratch->get(), infos[i], i == newest);
                    dds_sample_free(scratch->get(), desc, DDS_FREE_CONTENTS);
                }
            }
            ++visited;
        }
        ddsi_serdata_unref(data[i]);
    }
    return visited;
}

Result<int> take_loaned(dds_entity_t reader, int max, const BatchVisitor& visit) {
    void* samples[kMaxBatch] = {};
    dds_sample_info_t infos[kMaxBatch];
    const int n =
        dds_take(reader, samples, infos, static_cast<size_t>(max), static_cast<uint32_t>(max));
    if (n < 0) return check(n, "taking samples");
    const int newest = last_valid(infos, n);
    int visited = 0;
    for (int i = 0; i < n; ++i) {
        if (infos[i].valid_data) {
            visit(samples[i], infos[i], i == newest);
            ++visited;
        }
    }
    if (n > 0) dds_return_loan(reader, samples, n);
    return visited;
}

}  // namespace

Result<int> take_samples(dds_entity_t reader, const dds_topic_descriptor_t* desc, ReadMode mode,
                         int max, const SampleVisitor& visit) {
    return take_batch(reader, desc, mode, max,
                      [&visit](const void* s, const dds_sample_info_t& info, bool) { visit(s, info); });
}

Result<int> take_batch(dds_entity_t reader, const dds_topic_descriptor_t* desc, ReadMode mode,
                       int max, const BatchVisitor& visit) {
    if (max > kMaxBatch) max = kMaxBatch;
    if (max < 1) max = 1;
    if (mode == ReadMode::kZeroCopy) return take_zero_copy(reader, desc, max, visit);
    return take_loaned(reader, max, visit);
}

}  // namespace df::dds
