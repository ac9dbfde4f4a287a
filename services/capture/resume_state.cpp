#include "resume_state.hpp"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace df::capture {
namespace {

namespace fs = std::filesystem;

template <typename T>
bool parse_int(const std::string& text, T* value) {
    const char* end = text.data() + text.size();
    auto [p, ec] = std::from_chars(text.data(), end, *value);
    return ec == std::errc() && p == end;
}

Status bad(const std::string& path, int line, const std::string& what) {
    return Status(StatusCode::kInvalidArgument,
                  "resume file " + path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

Result<std::optional<ResumeState>> read_resume_state(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return std::optional<ResumeState>();
    std::ifstream in(path);
    if (!in || fs::is_directory(path, ec)) {
        return Status(StatusCode::kIoError, "cannot read resume file " + path);
    }
    std::map<std::string, std::pair<std::string, int>> fields;  // key -> (value, line)
    std::string text;
    for (int line = 1; std::getline(in, text); ++line) {
        if (text.empty() || text[0] == '#') continue;
        const size_t space = text.find(' ');
        if (space == std::string::npos || space == 0) {
            return bad(path, line, "expected 'key value', got '" + text + "'");
        }
        const std::string key = text.substr(0, space);
        if (!fields.emplace(key, std::make_pair(text.substr(space + 1), line)).second) {
            return bad(path, line, "'" + key + "' given twice");
        }
    }
    ResumeState s;
    auto field = [&](const char* key) -> const std::pair<std::string, int>* {
        auto it = fields.find(key);
        return it == fields.end() ? nullptr : &it->second;
    };
    for (const char* key :
         {"folder", "ns", "source_id", "loop", "last_sensor_ns", "frames_done", "finished"}) {
        if (field(key) == nullptr) return bad(path, 0, "no '" + std::string(key) + "' line");
    }
    s.folder = field("folder")->first;
    s.ns = field("ns")->first;
    auto number = [&](const char* key, auto* value) -> Status {
        const auto& [v, line] = *field(key);
        if (!parse_int(v, value))
            return bad(path, line, std::string(key) + " '" + v + "' is not an integer in range");
        return Status::ok();
    };
    DF_RETURN_IF_ERROR(number("source_id", &s.source_id));
    DF_RETURN_IF_ERROR(number("loop", &s.loop));
    DF_RETURN_IF_ERROR(number("last_sensor_ns", &s.last_sensor_ns));
    DF_RETURN_IF_ERROR(number("frames_done", &s.frames_done));
    int finished = 0;
    DF_RETURN_IF_ERROR(number("finished", &finished));
    if (finished != 0 && finished != 1) {
        return bad(path, field("finished")->second,
                   "finished must be 0 or 1, got " + std::to_string(finished));
    }
    if (s.last_sensor_ns < -1) {
        return bad(path, field("last_sensor_ns")->second, "last_sensor_ns must be >= -1");
    }
    s.finished = finished == 1;
    return std::optional<ResumeState>(s);
}

Status write_resume_state(const std::string& path, const ResumeState& s) {
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    std::ostringstream text;
    text << "# df_capture resume record: the last frame done (docs/hardening.md, Restarts)\n"
         << "folder " << s.folder << "\nns " << s.ns << "\nsource_id " << s.source_id << "\nloop "
         << s.loop << "\nlast_sensor_ns " << s.last_sensor_ns << "\nframes_done " << s.frames_done
         << "\nfinished " << (s.finished ? 1 : 0) << "\n";
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::trunc);
        out << text.str();
        out.close();
        if (!out) {
            return Status(StatusCode::kIoError,
                          "cannot write resume file " + tmp + ": " + std::strerror(errno));
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        return Status(StatusCode::kIoError,
                      "cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
    }
    return Status::ok();
}

std::string resume_mismatch(const ResumeState& saved, const ResumeState& current) {
    if (saved.folder != current.folder) {
        return "it is for folder " + saved.folder + ", not " + current.folder;
    }
    if (saved.ns != current.ns) return "it is for namespace " + saved.ns + ", not " + current.ns;
    if (saved.source_id != current.source_id) {
        return "it is for source_id " + std::to_string(saved.source_id) + ", not " +
               std::to_string(current.source_id);
    }
    return "";
}

}  // namespace df::capture
