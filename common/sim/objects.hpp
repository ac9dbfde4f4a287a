#pragma once
/// Things built from primitives, each in its own object frame (origin on the floor under it,
/// x forward, z up). Each builder adds its materials to the scene and returns the parts; use them
/// for a DynamicObject or place them as static furniture with place_static().
#include <string>
#include <vector>

#include "sim/scene.hpp"

namespace df::sim {

/// A car (COCO "car"): real proportions (4.2 x 1.76 x 1.45 m) times `scale`.
std::vector<Shape> make_car(Scene* scene, const Rgb& paint, double scale);
/// A four-legged chair (COCO "chair"), seat 0.46 m high, sitter faces +x.
std::vector<Shape> make_chair(Scene* scene, const Rgb& colour);
/// An office swivel chair (COCO "chair"), seat 0.44 m high, sitter faces +x.
std::vector<Shape> make_office_chair(Scene* scene, const Rgb& colour);
/// An upright wheeled suitcase (COCO "suitcase"), 0.42 wide, 0.25 deep, 0.68 high, front +x.
std::vector<Shape> make_suitcase(Scene* scene, const Rgb& colour, const PhotoLibrary* photos);
/// A toy bear sitting (COCO "teddy bear"), about 0.5 m high, facing +x.
std::vector<Shape> make_teddy_bear(Scene* scene, const Rgb& fur);
/// A potted plant (COCO "pottedplant"), about `height` m high.
std::vector<Shape> make_potted_plant(Scene* scene, double height, uint64_t seed);
/// An odd object of no COCO class: a chequered drum with rounded ends, lying on its side with
/// its axis along y, radius 0.2 m; its frame origin is the drum's centre (it rolls).
std::vector<Shape> make_roller(Scene* scene, const Rgb& a, const Rgb& b);
/// Another odd shape of no class: a lumpy stack (box, squashed ball, cone) about 0.6 m high.
std::vector<Shape> make_totem(Scene* scene, const Rgb& a, const Rgb& b);

}  // namespace df::sim
