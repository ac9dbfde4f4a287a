#include "sequence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace df::virtual_camera {
namespace {

bool env_number(const char* name, double* value, std::string* error) {
    const char* text = std::getenv(name);
    if (text == nullptr || *text == '\0') return true;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(v) || v <= 0.0) {
        *error = std::string(name) + "='" + text + "': expected a positive number";
        return false;
    }
    *value = v;
    return true;
}

bool env_flag(const char* name) {
    const char* text = std::getenv(name);
    return text != nullptr && std::string(text) == "1";
}

std::string join_path(const std::string& folder, const std::string& file) {
    if (!file.empty() && file.front() == '/') return file;
    if (!folder.empty() && folder.back() == '/') return folder + file;
    return folder + "/" + file;
}

// Reads a PNG with OpenCV; OpenCV reports problems by exception or an empty matrix.
cv::Mat read_image(const std::string& path, int flags, std::string* error) {
    cv::Mat image;
    try {
        image = cv::imread(path, flags);
    } catch (const cv::Exception& e) {
        *error = path + ": " + e.what();
        return {};
    }
    if (image.empty()) *error = path + ": missing or not a readable image";
    return image;
}

double median_depth_period_s(const std::vector<SequenceEntry>& entries) {
    std::vector<double> steps;
    for (size_t i = 1; i < entries.size(); ++i) {
        const double step = entries[i].depth_stamp_s - entries[i - 1].depth_stamp_s;
        if (step > 0.0) steps.push_back(step);
    }
    if (steps.empty()) return 1.0 / 30.0;
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    return steps[steps.size() / 2];
}

}  // namespace

bool Settings::from_env(Settings* out, std::string* error) {
    Settings s;
    if (!env_number("DF_VIRTUAL_CAMERA_DEPTH_SCALE", &s.depth_units_per_m, error)) return false;
    if (!env_number("DF_VIRTUAL_CAMERA_FX", &s.fx, error)) return false;
    if (!env_number("DF_VIRTUAL_CAMERA_FY", &s.fy, error)) return false;
    s.lockstep = env_flag("DF_VIRTUAL_CAMERA_LOCKSTEP");
    s.loop = env_flag("DF_VIRTUAL_CAMERA_LOOP");
    *out = s;
    return true;
}

bool Sequence::load(const std::string& folder, Sequence* out, std::string* error) {
    const std::string list_path = join_path(folder, "associations.txt");
    std::ifstream list(list_path);
    if (!list) {
        *error = list_path +
                 ": not found (a virtual camera folder needs associations.txt with lines "
                 "'t_rgb rgb_path t_depth depth_path')";
        return false;
    }
    Sequence seq;
    seq.folder = folder;
    std::string text;
    for (int line = 1; std::getline(list, text); ++line) {
        const size_t first = text.find_first_not_of(" \t\r");
        if (first == std::string::npos || text[first] == '#') continue;
        std::istringstream fields(text);
        SequenceEntry entry;
        std::string rest;
        if (!(fields >> entry.rgb_stamp_s >> entry.rgb_path >> entry.depth_stamp_s >>
              entry.depth_path) ||
            (fields >> rest)) {
            *error = list_path + ":" + std::to_string(line) +
                     ": expected 't_rgb rgb_path t_depth depth_path', got '" + text + "'";
            return false;
        }
        entry.rgb_path = join_path(folder, entry.rgb_path);
        entry.depth_path = join_path(folder, entry.depth_path);
        entry.line = line;
        seq.entries.push_back(std::move(entry));
    }
    if (seq.entries.empty()) {
        *error = list_path + ": no frames listed";
        return false;
    }
    const cv::Mat first_depth = read_image(seq.entries[0].depth_path, cv::IMREAD_ANYDEPTH, error);
    if (first_depth.empty()) return false;
    seq.width = first_depth.cols;
    seq.height = first_depth.rows;
    seq.period_s = median_depth_period_s(seq.entries);
    *out = std::move(seq);
    return true;
}

bool read_frame(const Sequence& sequence, size_t index, double depth_units_per_m, FramePair* out,
                std::string* error) {
    const SequenceEntry& entry = sequence.entries.at(index);
    const std::string where = " (associations.txt:" + std::to_string(entry.line) + ")";
    const cv::Mat bgr = read_image(entry.rgb_path, cv::IMREAD_COLOR, error);
    if (bgr.empty()) {
        *error += where;
        return false;
    }
    const cv::Mat raw = read_image(entry.depth_path, cv::IMREAD_ANYDEPTH, error);
    if (raw.empty()) {
        *error += where;
        return false;
    }
    if (raw.type() != CV_16UC1) {
        *error = entry.depth_path + ": expected a 16-bit single-channel PNG" + where;
        return false;
    }
    const cv::Size size(sequence.width, sequence.height);
    if (bgr.size() != size || raw.size() != size) {
        *error = entry.rgb_path + ", " + entry.depth_path +
                 ": size differs from the first frame (" + std::to_string(size.width) + "x" +
                 std::to_string(size.height) + ")" + where;
        return false;
    }
    out->rgb.resize(static_cast<size_t>(size.area()) * 3);
    cv::Mat rgb(size, CV_8UC3, out->rgb.data());
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);

    out->depth_mm.resize(static_cast<size_t>(size.area()));
    const double mm_per_unit = 1000.0 / depth_units_per_m;
    for (int y = 0; y < size.height; ++y) {
        const uint16_t* src = raw.ptr<uint16_t>(y);
        uint16_t* dst = out->depth_mm.data() + static_cast<size_t>(y) * size.width;
        for (int x = 0; x < size.width; ++x) {
            const long mm = std::lround(src[x] * mm_per_unit);
            dst[x] = static_cast<uint16_t>(std::min(mm, 65535L));
        }
    }
    // OpenNI stamps are unsigned microseconds.
    out->rgb_stamp_us = static_cast<uint64_t>(std::llround(std::max(0.0, entry.rgb_stamp_s) * 1e6));
    out->depth_stamp_us =
        static_cast<uint64_t>(std::llround(std::max(0.0, entry.depth_stamp_s) * 1e6));
    return true;
}

}  // namespace df::virtual_camera
