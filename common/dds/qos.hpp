#pragma once
/// QoS per kind of topic, chosen once here (see docs/topics.md for the reasoning).
///
/// All profiles are KEEP_LAST + VOLATILE + automatic liveliness + infinite deadline, which is
/// what Cyclone needs to carry a topic over iceoryx shared memory.
///  - kFrames:  RELIABLE, depth 4. Big samples; a slow local reader loses the oldest frames
///              (shared memory has no back-pressure), a remote reader throttles the writer.
///  - kResults: RELIABLE, depth 16. Per-frame results (detections, segments, poses): small or
///              medium, every one matters to the join.
///  - kStatus:  RELIABLE, depth 64. Stage status/acks; tiny, must not be lost.
///  - kTap:     BEST_EFFORT, depth 16, for debugging readers: matches any writer.
#include <dds/dds.h>

#include <memory>

namespace df::dds {

enum class QosProfile { kFrames, kResults, kStatus, kTap };

struct QosDeleter {
    void operator()(dds_qos_t* q) const { dds_delete_qos(q); }
};
using QosPtr = std::unique_ptr<dds_qos_t, QosDeleter>;

/// A new QoS object for a profile; depth 0 keeps the profile's default depth.
QosPtr make_qos(QosProfile profile, int32_t depth = 0);
const char* to_string(QosProfile profile);

}  // namespace df::dds
