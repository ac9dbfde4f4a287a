#pragma once
/// Validation of topic samples at the boundary: a sample from the network is untrusted (any
/// host on the domain can publish), so every consumer checks it before any view or copy.
/// check_sample() verifies sizes against the fixed capacities of idl/df_msgs.idl and every
/// field a consumer relies on (finite, positive, in range, enums in range, counts within
/// capacity, label values within the announced count). The message names the field, the value
/// and the limit, e.g. "RgbdFrame.width 1000 > MAX_WIDTH 640".
#include <cstdint>
#include <map>
#include <string>

#include "core/status.hpp"
#include "dds/msg_types.hpp"
#include "df_msgs.h"

namespace df::dds {

Status check_sample(const df_msg_Header& header);
Status check_sample(const df_msg_RgbdFrame& frame);
Status check_sample(const df_msg_CompressedImage& image);
Status check_sample(const df_msg_Detections& detections);
Status check_sample(const df_msg_GeometricSegments& segments);
Status check_sample(const df_msg_ObjectSegments& segments);
Status check_sample(const df_msg_CameraPose& pose);
Status check_sample(const df_msg_ObjectPoses& poses);
Status check_sample(const df_msg_MapCloud& cloud);
Status check_sample(const df_msg_StageStatus& status);

/// The check of the type `type` describes, for tools that handle any topic (tap).
Status check_sample(const TypeInfo& type, const void* sample);

/// A sample that passed check_sample(); the converters in msg_convert.hpp take only these, so
/// no caller can view or copy an unchecked sample. Aliases the sample (valid while it is).
template <typename T>
class Checked {
  public:
    /// The checked sample, or the check's error.
    static Result<Checked> make(const T& sample) {
        if (Status s = check_sample(sample); !s) return s;
        return Checked(sample);
    }
    const T& get() const { return *sample_; }
    const T& operator*() const { return *sample_; }
    const T* operator->() const { return sample_; }

  private:
    explicit Checked(const T& sample) : sample_(&sample) {}
    const T* sample_;
};

/// check_sample() as a Checked wrapper: `auto c = dds::checked(frame); if (!c) ...`.
template <typename T>
Result<Checked<T>> checked(const T& sample) {
    return Checked<T>::make(sample);
}

/// "writer <GUID>" of the sample's publication (from the reader's matched publications), or
/// "writer handle <n>" when the writer is no longer known.
std::string writer_of(dds_entity_t reader, const dds_sample_info_t& info);

/// Logs rejected samples, one line per rejection, naming topic, writer, sequence number and the
/// check's message; identical rejections (same topic, writer and message) are logged at most
/// once per `interval_ns` with a count of those left out, so a hostile writer cannot flood.
class RejectLog {
  public:
    explicit RejectLog(int64_t interval_ns = 5'000'000'000) : interval_ns_(interval_ns) {}
    /// Logs (or counts) one rejection; returns true when a line was written.
    /// `now_ns`: a monotonic clock.
    bool report(const std::string& topic, const std::string& writer, uint64_t seq,
                const Status& why, int64_t now_ns);
    /// The same on the monotonic clock.
    bool report(const std::string& topic, const std::string& writer, uint64_t seq,
                const Status& why);
    /// Rejections seen in all (logged or not).
    uint64_t total() const { return total_; }

  private:
    struct Entry {
        int64_t last_ns = 0;
        uint64_t left_out = 0;
    };
    int64_t interval_ns_;
    uint64_t total_ = 0;
    std::map<std::string, Entry> seen_;
};

/// A consumer's boundary: the sample checked; when it fails the check, the rejection is logged
/// to `rejects` naming `topic` and the sample's writer (looked up on `reader`).
template <typename T>
Result<Checked<T>> accept(const T& sample, dds_entity_t reader, const std::string& topic,
                          const dds_sample_info_t& info, RejectLog& rejects) {
    auto c = Checked<T>::make(sample);
    if (!c) {
        rejects.report(topic, writer_of(reader, info), sample.header.seq, c.status());
    }
    return c;
}

}  // namespace df::dds
