#pragma once
/// The topic types of idl/df_msgs.idl as the DDS layer sees them: compile-time traits for the
/// typed Writer/Reader, and a run-time table for tools that handle any topic (tap).
#include <string>
#include <vector>

#include "dds/qos.hpp"
#include "df_msgs.h"

namespace df::dds {

/// Run-time description of one topic type.
struct TypeInfo {
    const char* name;  ///< IDL name as DDS announces it, e.g. "df::msg::RgbdFrame"
    const dds_topic_descriptor_t* descriptor;
    QosProfile profile;  ///< default QoS profile for topics of this type
    bool fixed_size() const { return (descriptor->m_flagset & DDS_TOPIC_FIXED_SIZE) != 0; }
};

/// Every top-level topic type of the pipeline.
const std::vector<TypeInfo>& all_types();
/// The type with this DDS type name, or nullptr.
const TypeInfo* find_type(const std::string& type_name);

template <typename T>
struct MsgTraits;

#define DF_DECLARE_MSG(T, PROFILE)                                                       \
    template <>                                                                          \
    struct MsgTraits<df_msg_##T> {                                                       \
        static const dds_topic_descriptor_t* descriptor() { return &df_msg_##T##_desc; } \
        static constexpr const char* kName = "df::msg::" #T;                             \
        static constexpr QosProfile kProfile = QosProfile::PROFILE;                      \
    };

DF_DECLARE_MSG(RgbdFrame, kFrames)
DF_DECLARE_MSG(CompressedImage, kResults)
DF_DECLARE_MSG(Detections, kResults)
DF_DECLARE_MSG(GeometricSegments, kResults)
DF_DECLARE_MSG(ObjectSegments, kResults)
DF_DECLARE_MSG(CameraPose, kResults)
DF_DECLARE_MSG(ObjectPoses, kResults)
DF_DECLARE_MSG(MapCloud, kFrames)
DF_DECLARE_MSG(StageStatus, kStatus)
#undef DF_DECLARE_MSG

/// Default topic names (relative to a namespace, see topic_name()).
namespace topics {
inline constexpr const char* kFrames = "frames";
inline constexpr const char* kColorSmall = "color_small";
inline constexpr const char* kDetections = "detections";
inline constexpr const char* kGeometricSegments = "geometric_segments";
inline constexpr const char* kObjectSegments = "object_segments";
inline constexpr const char* kCameraPose = "camera_pose";
/// df::msg::ObjectSegments: what the SLAM service left out of the static map per frame.
inline constexpr const char* kInvalidMask = "invalid_mask";
inline constexpr const char* kObjectPoses = "object_poses";
inline constexpr const char* kStageStatus = "stage_status";
/// df::msg::MapCloud: the maps, thinned, at a low rate (for viewing).
inline constexpr const char* kMapCloud = "map_cloud";
}  // namespace topics

/// "<ns>/<name>", e.g. topic_name("df", "frames") == "df/frames". Tests use a unique ns,
/// because shared memory leaks samples across domains and partitions in Cyclone 0.10.
std::string topic_name(const std::string& ns, const std::string& name);

/// Copies text into a fixed char array, always NUL-terminated (truncated if needed).
template <size_t N>
void set_name(char (&dst)[N], const std::string& text) {
    const size_t n = text.size() < N - 1 ? text.size() : N - 1;
    text.copy(dst, n);
    dst[n] = '\0';
}
template <size_t N>
std::string get_name(const char (&src)[N]) {
    size_t n = 0;
    while (n < N && src[n] != '\0') ++n;
    return std::string(src, n);
}

}  // namespace df::dds
