#pragma once
/// Typed reader. take() hands each new sample to a callback as a const reference that is valid
/// only during the call. Over shared memory (ReadMode::kZeroCopy) the reference points into the
/// iceoryx chunk itself: no copy at all; samples from the network are deserialized first.
#include <functional>
#include <memory>
#include <string>

#include "dds/endpoint.hpp"
#include "dds/msg_types.hpp"

namespace df::dds {

enum class ReadMode {
    kZeroCopy,  ///< dds_takecdr; reads shared-memory chunks in place
    kLoan,      ///< dds_take with reader loans (Cyclone copies out of shared memory)
};

using SampleVisitor = std::function<void(const void* sample, const dds_sample_info_t& info)>;
/// As SampleVisitor, and told whether the sample is the newest of those taken together (the
/// last one with valid data): a stage that stays current copies only that one out of the loan.
using BatchVisitor =
    std::function<void(const void* sample, const dds_sample_info_t& info, bool newest)>;

/// Untyped take used by Reader<T> and by tools that handle any type (tap). Calls visit for each
/// valid sample (at most max); returns how many were visited.
Result<int> take_samples(dds_entity_t reader, const dds_topic_descriptor_t* desc, ReadMode mode,
                         int max, const SampleVisitor& visit);
Result<int> take_batch(dds_entity_t reader, const dds_topic_descriptor_t* desc, ReadMode mode,
                       int max, const BatchVisitor& visit);

template <typename T>
class Reader {
  public:
    static Result<Reader> create(const Participant& participant, const std::string& topic,
                                 EndpointOptions options = {MsgTraits<T>::kProfile},
                                 ReadMode mode = ReadMode::kZeroCopy) {
        auto r = create_reader(participant, MsgTraits<T>::descriptor(), topic, options);
        if (!r) return r.status();
        return Reader(std::move(*r), topic, mode);
    }

    /// Takes up to max new samples, calling fn(const T&, const dds_sample_info_t&) for each.
    template <typename Fn>
    Result<int> take(Fn&& fn, int max = 16) {
        return take_samples(reader_.get(), MsgTraits<T>::descriptor(), mode_, max,
                            [&fn](const void* s, const dds_sample_info_t& info) {
                                fn(*static_cast<const T*>(s), info);
                            });
    }

    /// As take(), calling fn(const T&, const dds_sample_info_t&, bool newest): newest is true
    /// for the last valid sample of the batch only.
    template <typename Fn>
    Result<int> take_batch(Fn&& fn, int max = 16) {
        return dds::take_batch(reader_.get(), MsgTraits<T>::descriptor(), mode_, max,
                               [&fn](const void* s, const dds_sample_info_t& info, bool newest) {
                                   fn(*static_cast<const T*>(s), info, newest);
                               });
    }

    dds_entity_t get() const { return reader_.get(); }
    const std::string& topic() const { return topic_; }
    uint32_t matched_writers() const { return dds::matched_writers(reader_.get()); }

  private:
    Reader(Entity r, std::string topic, ReadMode mode)
        : reader_(std::move(r)), topic_(std::move(topic)), mode_(mode) {}
    Entity reader_;
    std::string topic_;
    ReadMode mode_;
};

}  // namespace df::dds
