#pragma once
/// The static scene: an office room (textured walls, wooden floor, tiled ceiling) with a desk,
/// office chairs, a monitor showing a photo, a bookshelf, a sofa with a teddy bear, plants,
/// framed photos on the walls, a whiteboard, a door, a window and ceiling lamps.
#include <array>

#include "sim/scene.hpp"

namespace df::sim {

/// Places the presets need to know about.
struct Office {
    Vec3 desk_centre = Vec3(0, 2.4, 0.745);  ///< top surface centre, world metres
    std::array<Iso3, 2> seats;               ///< world_T_root of a person sitting at the desk
    double seat_height_m = 0.45;
};

/// Builds the room into `scene` (room, statics, lights). The layout is fixed; `seed` varies
/// colours and small items. `photos` may be null (decals then show grey).
Office build_office(Scene* scene, const PhotoLibrary* photos, uint64_t seed);

/// A framed photo (thin box, front +x), photo aspect kept, `height_m` high without the frame.
std::vector<Shape> make_picture(Scene* scene, const PhotoLibrary* photos, const std::string& photo,
                                double height_m);
/// A flat screen on a stand (COCO "tvmonitor") showing `photo`, front +x.
std::vector<Shape> make_monitor(Scene* scene, const PhotoLibrary* photos, const std::string& photo);
/// A bookshelf 1.0 wide, 1.9 high, 0.32 deep, full of books, front +x.
std::vector<Shape> make_bookshelf(Scene* scene, uint64_t seed);
/// A two-seat sofa (COCO "sofa") 1.9 wide, front +x.
std::vector<Shape> make_sofa(Scene* scene, const Rgb& colour);

}  // namespace df::sim
