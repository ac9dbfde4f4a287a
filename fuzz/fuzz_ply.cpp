// The PLY reader (maps, models, evaluation) on any file, ASCII or binary. Property: a cloud it
// returns has one normal, colour and extra value per point, and only finite positions.
// (Not check(): by design a partial group such as "blue" alone is read as an extra property,
// which check() refuses to write.)
#include <cmath>

#include "fuzz_util.hpp"
#include "io/ply/ply.hpp"

using namespace df;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::as_file("ply", data, size, ".ply");
    io::PlyReadInfo info;
    auto cloud = io::read_ply(path, &info);
    if (!cloud) return 0;
    const size_t n = cloud->size();
    DF_FUZZ_CHECK(cloud->normals.empty() || cloud->normals.size() == n);
    DF_FUZZ_CHECK(cloud->colours.empty() || cloud->colours.size() == n);
    for (const auto& s : cloud->scalars) DF_FUZZ_CHECK(s.values.size() == n);
    for (const auto& p : cloud->positions) DF_FUZZ_CHECK(p.allFinite());
    return 0;
}
