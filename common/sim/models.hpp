#pragma once
/// Ground-truth models: points sampled on the visible surfaces of the static scene (world frame)
/// and of each rigid object (object frame), coloured with the surface's albedo.
#include <cstdint>

#include "io/ply/ply.hpp"
#include "sim/scene.hpp"

namespace df::sim {

/// Room faces and static furniture, world frame: positions (metres), unit outward normals and
/// colours. Points inside other solids or behind the room's walls (faces resting on the floor,
/// the back of a picture) are left out.
io::PointCloud sample_static_model(const Scene& scene, double spacing_m, uint64_t seed);

/// The parts of object `index` that hang on its root (bone -1), in the object frame; points
/// inside other parts of the object are left out.
io::PointCloud sample_object_model(const Scene& scene, size_t index, double spacing_m,
                                   uint64_t seed);

}  // namespace df::sim
