#pragma once
/// What a run writes about its object maps (docs/objects.md), beside the static map:
///   <dir>/objects.json      the objects table: id, class, first and last frame, frames tracked,
///                           surfels, state, and the two files below
///   <dir>/objects/<id>.txt  world_T_object (TUM format) of every frame the object was tracked
///   <dir>/objects/<id>.ply  the object's model in its own frame (binary PLY as map.ply)
/// `df_eval run` reads them, with the per-frame object_masks/ (MaskOutputs), to associate the
/// estimated objects with ground-truth ones.
#include <functional>
#include <string>

#include "core/status.hpp"
#include "objects/object_maps.hpp"

namespace df::objects {

/// The class name of a class id ("car"), for the table.
using ClassNames = std::function<std::string(int class_id)>;

/// Writes the three outputs under `dir` (which exists). `stable_only`: only stable surfels in
/// the models (a map younger than that has none: then every surfel). Every file is attempted;
/// the first error (kIoError naming the file) is returned.
Status write_objects(const std::string& dir, const ObjectMaps& maps, const ClassNames& names,
                     bool stable_only);

/// One line per object: "object 3 car: tracked 212 frames (10..250), 4100 surfels, active".
std::string describe_objects(const ObjectMaps& maps, const ClassNames& names);

}  // namespace df::objects
