#include "objects/object_io.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/tum/trajectory.hpp"

namespace df::objects {
namespace {

std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) out += c;
    }
    return out + "\"";
}

uint64_t last_frame(const ObjectMap& o) { return std::max(o.first_frame, o.last_seen_frame); }

}  // namespace

Status write_objects(const std::string& dir, const ObjectMaps& maps, const ClassNames& names,
                     bool stable_only) {
    std::error_code ec;
    std::filesystem::create_directories(dir + "/objects", ec);
    if (ec) {
        return error(StatusCode::kIoError, "cannot create '" + dir + "/objects': " + ec.message());
    }
    Status first = Status::ok();
    std::ostringstream j;
    j << "{\n  \"objects\": [";
    bool comma = false;
    for (const ObjectMap& o : maps.objects()) {
        const std::string id = std::to_string(o.id);
        const std::string trajectory = "objects/" + id + ".txt";
        const std::string model = "objects/" + id + ".ply";
        Status t = io::write_tum_trajectory(dir + "/" + trajectory, o.trajectory);
        const bool stable = stable_only && o.map.map().stable_count() > 0;
        Status m = o.map.map().write_ply(dir + "/" + model, stable);
        if (first.is_ok()) first = t.is_ok() ? m : t;
        j << (comma ? "," : "") << "\n    {\"id\": " << o.id << ", \"class_id\": " << o.class_id
          << ", \"class_name\": " << json_string(names ? names(o.class_id) : "")
          << ", \"score\": " << o.score << ", \"first_frame\": " << o.first_frame
          << ", \"last_frame\": " << last_frame(o) << ", \"frames_tracked\": " << o.frames_tracked
          << ", \"early_poses_refined\": " << o.early_poses_refined
          << ", \"surfels\": " << o.map.map().size() << ", \"state\": \"" << to_string(o.state)
          << "\", \"trajectory\": \"" << trajectory
          << "\", \"model\": " << (m.is_ok() ? "\"" + model + "\"" : std::string("null")) << "}";
        comma = true;
    }
    const ObjectCounters& c = maps.counters();
    j << "\n  ],\n  \"counters\": {\"created\": " << c.created << ", \"revived\": " << c.revived
      << ", \"retired\": " << c.retired << ", \"refused_by_cap\": " << c.refused_by_cap
      << ", \"surfels_rejected_by_capacity\": " << c.surfels_rejected_by_capacity << "}\n}\n";
    const std::string file = dir + "/objects.json";
    std::ofstream out(file);
    out << j.str();
    if (!out && first.is_ok()) first = Status(StatusCode::kIoError, "cannot write '" + file + "'");
    return first;
}

std::string describe_objects(const ObjectMaps& maps, const ClassNames& names) {
    std::ostringstream s;
    for (const ObjectMap& o : maps.objects()) {
        s << "object " << o.id << " " << (names ? names(o.class_id) : std::to_string(o.class_id))
          << ": tracked " << o.frames_tracked << " frames (" << o.first_frame << ".."
          << last_frame(o) << "), " << o.map.map().size() << " surfels, " << to_string(o.state)
          << "\n";
    }
    const ObjectCounters& c = maps.counters();
    if (c.refused_by_cap > 0 || c.surfels_rejected_by_capacity > 0) {
        s << "caps hit: " << c.refused_by_cap << " object creations refused (max_objects), "
          << c.surfels_rejected_by_capacity << " surfels refused (max_surfels)\n";
    }
    return s.str();
}

}  // namespace df::objects
