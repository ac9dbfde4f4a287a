// ObjectMaps as a checkpoint keeps them: state() and restore() (the per-frame steps are in
// object_maps.cpp, object_mapping.cpp and object_creation.cpp).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "objects/object_maps.hpp"

namespace df::objects {

ObjectMapsState ObjectMaps::state() const {
    ObjectMapsState s;
    s.counters = counters_;
    s.next_id = next_id_;
    for (const ObjectMap& o : objects_) {
        ObjectMapState m;
        m.id = o.id;
        m.class_id = o.class_id;
        m.score = o.score;
        m.state = o.state;
        m.first_frame = o.first_frame;
        m.last_seen_frame = o.last_seen_frame;
        m.frames_tracked = o.frames_tracked;
        m.frames_lost = o.frames_lost;
        m.world_T_object = o.map.world_T_map();
        m.body_motion = o.body_motion;
        m.mover = o.mover;
        m.trajectory = o.trajectory;
        m.surfels = o.map.map().surfels();
        m.surfels_rejected_by_capacity = o.map.map().total_rejected_by_capacity();
        s.objects.push_back(std::move(m));
    }
    return s;
}

Status ObjectMaps::restore(ObjectMapsState state) {
    std::vector<ObjectMap> objects;
    int next_id = std::max(state.next_id, 1);
    for (ObjectMapState& m : state.objects) {
        const std::string where = "object " + std::to_string(m.id);
        if (m.id < 1) return error(StatusCode::kInvalidArgument, where + ": id must be >= 1");
        for (const ObjectMap& o : objects)
            if (o.id == m.id) return error(StatusCode::kInvalidArgument, where + ": id repeats");
        if (!m.world_T_object.matrix().allFinite() || !m.body_motion.matrix().allFinite())
            return error(StatusCode::kInvalidArgument, where + ": pose is not finite");
        ObjectMap o(m.id, map_config_);
        o.class_id = m.class_id;
        o.score = m.score;
        o.state = m.state;
        o.first_frame = m.first_frame;
        o.last_seen_frame = m.last_seen_frame;
        o.frames_tracked = m.frames_tracked;
        o.frames_lost = m.frames_lost;
        o.map.set_world_T_map(m.world_T_object);
        o.body_motion = m.body_motion;
        o.mover = m.mover;
        o.trajectory = std::move(m.trajectory);
        // The kept early views are not in a checkpoint: a restored map's first poses stay as
        // they are (refined already, or as tracked).
        o.early_refined = true;
        DF_RETURN_IF_ERROR(o.map.map()
                               .restore(std::move(m.surfels), m.surfels_rejected_by_capacity)
                               .with_context(where));
        next_id = std::max(next_id, m.id + 1);
        objects.push_back(std::move(o));
    }
    objects_ = std::move(objects);
    candidates_.clear();
    counters_ = state.counters;
    next_id_ = next_id;
    return Status::ok();
}

}  // namespace df::objects
