#include "io/tum/intrinsics_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/tum/tum_folder.hpp"

namespace df::io {

Result<IntrinsicsFile> read_intrinsics_file(const std::string& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) {
        return error(StatusCode::kNotFound, file + " does not exist");
    }
    std::ifstream in(file);
    if (!in || !std::filesystem::is_regular_file(file, ec)) {
        return error(StatusCode::kIoError, "cannot read " + file + " (not a readable file)");
    }
    std::string line;
    int number = 0;
    int values_line = 0;
    IntrinsicsFile out;
    while (std::getline(in, line)) {
        ++number;
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::string where = file + ":" + std::to_string(number);
        if (values_line > 0) {  // one camera per file: a second line is not silently ignored
            return error(StatusCode::kInvalidArgument,
                         where + ": a second intrinsics line (the first is line " +
                             std::to_string(values_line) + "); the file holds one camera");
        }
        values_line = number;
        std::istringstream s(line);
        Intrinsics& k = out.intrinsics;
        std::string extra;
        if (!(s >> k.fx >> k.fy >> k.cx >> k.cy >> out.width >> out.height >>
              out.depth_units_per_m) ||
            (s >> extra)) {
            return error(StatusCode::kInvalidArgument,
                         where +
                             ": expected 'fx fy cx cy width height depth_units_per_m', found '" +
                             line + "'");
        }
        if (out.width < 1 || out.height < 1 || out.width > kMaxWidth || out.height > kMaxHeight) {
            return error(StatusCode::kInvalidArgument,
                         where + ": image size " + std::to_string(out.width) + "x" +
                             std::to_string(out.height) + ", allowed: 1x1 to " +
                             std::to_string(kMaxWidth) + "x" + std::to_string(kMaxHeight));
        }
        DF_RETURN_IF_ERROR(check_intrinsics(k, out.width, out.height, where));
        const double units = out.depth_units_per_m;
        if (!(std::isfinite(units) && units > 0 && units <= 1e6)) {
            std::ostringstream v;
            v << units;
            return error(StatusCode::kInvalidArgument,
                         where + ": depth_units_per_m is " + v.str() + ", allowed: > 0 and <= 1e6");
        }
    }
    if (values_line == 0) return error(StatusCode::kInvalidArgument, file + ": no intrinsics line");
    return out;
}

Result<TumFolderConfig> tum_folder_config(const std::string& folder, const std::string& preset) {
    TumFolderConfig config;
    config.folder = folder;
    auto file = read_intrinsics_file(folder + "/intrinsics.txt");
    if (file) {
        config.intrinsics = file->intrinsics;
        config.width = file->width;
        config.height = file->height;
        config.depth_units_per_m = file->depth_units_per_m;
        return config;
    }
    if (file.status().code() != StatusCode::kNotFound) return file.status();
    auto intrinsics = intrinsics_preset(preset);
    if (!intrinsics) return intrinsics.status();
    config.intrinsics = *intrinsics;
    if (preset == "7scenes") {
        config.depth_units_per_m = 1000.0;
        config.depth_invalid_value = 65535;
    }
    return config;
}

}  // namespace df::io
