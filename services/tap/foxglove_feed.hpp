#pragma once
/// The tap's samples into Foxglove views (common/foxglove/scene.hpp): frames, detections, object
/// segments, camera and object poses, the map. Shared by `record --foxglove` and `bridge`.
#include <string>
#include <vector>

#include "dds/msg_types.hpp"
#include "foxglove/scene.hpp"

namespace df::tap {

/// Whether samples of this type make any Foxglove view.
bool has_foxglove_view(const dds::TypeInfo& type);

/// The Foxglove messages one sample of `type` makes (none for a sample that fails its check or a
/// type without a view).
std::vector<foxglove::Message> foxglove_view(foxglove::SceneEncoder& encoder,
                                             const dds::TypeInfo& type, const void* sample);

/// The namespace of a topic ("df" of "df/frames"; "" without a slash).
std::string topic_ns(const std::string& topic);

}  // namespace df::tap
