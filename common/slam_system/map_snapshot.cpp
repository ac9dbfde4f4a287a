#include "slam_system/map_snapshot.hpp"

#include <algorithm>

namespace df::slam {
namespace {

uint8_t channel(float v) { return static_cast<uint8_t>(std::clamp(v, 0.f, 255.f) + 0.5f); }

}  // namespace

MapSnapshot map_snapshot(const SlamSystem& system, size_t max_points) {
    MapSnapshot out;
    const map::SurfelMap& background = system.static_map();
    size_t total = 0;
    for (const map::Surfel& s : background.surfels()) total += background.is_stable(s) ? 1 : 0;
    for (const objects::ObjectMap& o : system.object_maps().objects()) {
        if (o.state == objects::ObjectState::kActive) total += o.map.map().surfels().size();
    }
    out.surfels = total;
    if (max_points == 0) return out;
    const size_t step = std::max<size_t>(1, (total + max_points - 1) / max_points);
    out.points.reserve(std::min(total, max_points));
    size_t n = 0;
    for (const map::Surfel& s : background.surfels()) {
        if (!background.is_stable(s) || n++ % step != 0) continue;
        out.points.push_back(
            {s.position, channel(s.colour.x()), channel(s.colour.y()), channel(s.colour.z()), 0});
    }
    for (const objects::ObjectMap& o : system.object_maps().objects()) {
        if (o.state != objects::ObjectState::kActive) continue;
        const auto& surfels = o.map.map().surfels();
        if (surfels.empty()) continue;
        const Eigen::Isometry3f world_T_object = o.map.world_T_map().cast<float>();
        ObjectExtent e{o.id, o.class_id, surfels.front().position, surfels.front().position};
        for (const map::Surfel& s : surfels) {
            e.min = e.min.cwiseMin(s.position);
            e.max = e.max.cwiseMax(s.position);
            if (n++ % step != 0) continue;
            out.points.push_back({world_T_object * s.position, channel(s.colour.x()),
                                  channel(s.colour.y()), channel(s.colour.z()),
                                  static_cast<uint32_t>(o.id)});
        }
        out.objects.push_back(e);
    }
    if (out.points.size() > max_points) out.points.resize(max_points);
    return out;
}

}  // namespace df::slam
