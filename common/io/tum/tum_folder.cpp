#include "io/tum/tum_folder.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <utility>

#include "io/tum/image_header.hpp"
#include "io/tum/image_read.hpp"
#include "io/tum/image_text.hpp"

namespace df::io {
namespace fs = std::filesystem;

using detail::load_depth;
using detail::load_rgb;
using detail::size_name;
using detail::SizeRule;

namespace {

constexpr const char* kExpectedLayout =
    "expected a folder with rgb.txt and depth.txt (lines 'timestamp path') or associations.txt";

/// The line as quoted in a message: long lines are cut so the message stays one readable line.
std::string quote(const std::string& text) {
    constexpr size_t kMax = 80;
    if (text.size() <= kMax) return "'" + text + "'";
    return "'" + text.substr(0, kMax) + "...'";
}

std::string at(const std::string& file, int line) { return file + ":" + std::to_string(line); }

/// e.g. "1 malformed line", "3 malformed lines".
std::string malformed_lines(size_t count) {
    return std::to_string(count) + (count == 1 ? " malformed line" : " malformed lines");
}

/// Parses fields[first], fields[first + 1] as "timestamp path"; on failure says what was wrong.
bool parse_stamped_path(const TumTextLine& line, size_t first, StampReader* stamps,
                        StampedPath* out, std::string* what) {
    auto stamp = stamps->read(line.fields[first], line.line);
    if (!stamp) {
        *what = stamp.status().message();
        return false;
    }
    out->stamp_ns = *stamp;
    out->path = line.fields[first + 1];
    out->line = line.line;
    return true;
}

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

Result<Intrinsics> intrinsics_preset(const std::string& name) {
    std::string key = name;
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (key == "fr1") return Intrinsics{517.3, 516.5, 318.6, 255.3};
    if (key == "fr2") return Intrinsics{520.9, 521.0, 325.1, 249.7};
    if (key == "fr3") return Intrinsics{535.4, 539.2, 320.1, 247.6};
    if (key == "7scenes") return Intrinsics{585.0, 585.0, 320.0, 240.0};
    return error(StatusCode::kInvalidArgument,
                 "unknown intrinsics preset '" + name + "' (known: fr1, fr2, fr3, 7scenes)");
}

bool parse_tum_stamp(const std::string& field, double* stamp_s) {
    auto stamp = parse_stamp(field);
    if (!stamp) return false;
    *stamp_s = static_cast<double>(stamp->ns) / 1e9;
    return true;
}

Status check_intrinsics(const Intrinsics& k, int width, int height, const std::string& where) {
    auto outside = [&](const char* name, double value, double low, double high) {
        return error(StatusCode::kInvalidArgument,
                     where + ": " + name + " is " + number(value) + ", allowed [" + number(low) +
                         ", " + number(high) + "] for " + std::to_string(width) + "x" +
                         std::to_string(height) + " images");
    };
    const double w = width, h = height;
    if (!(std::isfinite(k.fx) && k.fx >= 0.05 * w && k.fx <= 20 * w))
        return outside("fx", k.fx, 0.05 * w, 20 * w);
    if (!(std::isfinite(k.fy) && k.fy >= 0.05 * w && k.fy <= 20 * w))
        return outside("fy", k.fy, 0.05 * w, 20 * w);
    if (!(std::isfinite(k.cx) && k.cx >= 0 && k.cx <= w)) return outside("cx", k.cx, 0, w);
    if (!(std::isfinite(k.cy) && k.cy >= 0 && k.cy <= h)) return outside("cy", k.cy, 0, h);
    return Status::ok();
}

Result<std::vector<TumTextLine>> read_tum_text_lines(const std::string& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return error(StatusCode::kNotFound, file + " does not exist");
    if (fs::is_directory(file, ec)) {
        return error(StatusCode::kIoError, file + " is a folder, expected a text file");
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) return error(StatusCode::kIoError, "cannot open " + file + " for reading");
    std::vector<TumTextLine> lines;
    std::string text;
    int number = 0;
    while (std::getline(in, text)) {
        ++number;
        if (!text.empty() && text.back() == '\r') text.pop_back();
        const size_t first = text.find_first_not_of(" \t");
        if (first == std::string::npos || text[first] == '#') continue;
        TumTextLine line;
        line.line = number;
        line.text = text;
        std::string field;
        for (char c : text) {
            if (c == ' ' || c == '\t' || c == ',') {
                if (!field.empty()) line.fields.push_back(std::move(field));
                field.clear();
            } else {
                field += c;
            }
        }
        if (!field.empty()) line.fields.push_back(std::move(field));
        lines.push_back(std::move(line));
    }
    if (in.bad()) return error(StatusCode::kIoError, "error while reading " + file);
    return lines;
}

Result<ListParse> parse_stamp_list(const std::string& file) {
    auto lines = read_tum_text_lines(file);
    if (!lines) return lines.status();
    ListParse parse;
    StampReader stamps;
    for (const TumTextLine& line : *lines) {
        // TUM's tools read the first two fields and ignore any after them; so do we.
        std::string what;
        StampedPath entry;
        if (line.fields.size() < 2) {
            what = "expected 'timestamp path', found " + quote(line.text);
        } else if (parse_stamped_path(line, 0, &stamps, &entry, &what)) {
            parse.entries.push_back(std::move(entry));
            continue;
        }
        parse.errors.push_back(at(file, line.line) + ": " + what);
    }
    return parse;
}

Result<AssociationsParse> parse_associations(const std::string& file) {
    auto lines = read_tum_text_lines(file);
    if (!lines) return lines.status();
    AssociationsParse parse;
    StampReader stamps;  // one unit for the file, rgb and depth columns alike
    for (const TumTextLine& line : *lines) {
        std::string what;
        AssociatedPair pair;
        if (line.fields.size() < 4) {
            what = "expected 't_rgb rgb_path t_depth depth_path', found " + quote(line.text);
        } else if (parse_stamped_path(line, 0, &stamps, &pair.rgb, &what) &&
                   parse_stamped_path(line, 2, &stamps, &pair.depth, &what)) {
            // Frames are played in file order: a stamp not after the previous frame's would be
            // a second pose for one instant or a step back in time.
            const AssociatedPair* last = parse.pairs.empty() ? nullptr : &parse.pairs.back();
            if (last == nullptr || pair.rgb.stamp_ns > last->rgb.stamp_ns) {
                parse.pairs.push_back(std::move(pair));
                continue;
            }
            what = "rgb time stamp " + line.fields[0] + " is not after line " +
                   std::to_string(last->rgb.line) + "'s (" + stamp_text(last->rgb.stamp_ns, 9) +
                   "); frames must be listed in time order, each once";
        }
        parse.errors.push_back(at(file, line.line) + ": " + what);
    }
    return parse;
}

std::vector<AssociatedPair> associate(const std::vector<StampedPath>& rgb,
                                      const std::vector<StampedPath>& depth,
                                      int64_t max_difference_ns) {
    std::vector<AssociatedPair> pairs;
    if (max_difference_ns <= 0 || rgb.empty() || depth.empty()) return pairs;

    // Candidates are found through the depth stamps in sorted order, so the cost stays
    // O((n + m) log m + candidates) instead of associate.py's all-pairs loop. Stamps are in
    // [0, INT64_MAX] so differences of two never overflow; the window ends are clamped.
    std::vector<size_t> depth_order(depth.size());
    std::iota(depth_order.begin(), depth_order.end(), size_t{0});
    std::stable_sort(depth_order.begin(), depth_order.end(),
                     [&](size_t a, size_t b) { return depth[a].stamp_ns < depth[b].stamp_ns; });

    struct Candidate {
        int64_t difference;
        size_t rgb, depth;
    };
    std::vector<Candidate> candidates;
    for (size_t r = 0; r < rgb.size(); ++r) {
        const int64_t a = rgb[r].stamp_ns;
        const int64_t low = a > max_difference_ns ? a - max_difference_ns : 0;
        auto it = std::lower_bound(depth_order.begin(), depth_order.end(), low,
                                   [&](size_t d, int64_t v) { return depth[d].stamp_ns < v; });
        for (; it != depth_order.end(); ++it) {
            const int64_t b = depth[*it].stamp_ns;
            const int64_t difference = b >= a ? b - a : a - b;
            if (b > a && difference >= max_difference_ns) break;
            if (difference < max_difference_ns) candidates.push_back({difference, r, *it});
        }
    }
    // associate.py sorts (difference, t_rgb, t_depth) tuples; list positions break exact ties.
    std::sort(candidates.begin(), candidates.end(), [&](const Candidate& x, const Candidate& y) {
        if (x.difference != y.difference) return x.difference < y.difference;
        if (rgb[x.rgb].stamp_ns != rgb[y.rgb].stamp_ns)
            return rgb[x.rgb].stamp_ns < rgb[y.rgb].stamp_ns;
        if (depth[x.depth].stamp_ns != depth[y.depth].stamp_ns) {
            return depth[x.depth].stamp_ns < depth[y.depth].stamp_ns;
        }
        return std::make_pair(x.rgb, x.depth) < std::make_pair(y.rgb, y.depth);
    });

    std::vector<bool> rgb_used(rgb.size(), false), depth_used(depth.size(), false);
    std::vector<std::pair<size_t, size_t>> chosen;
    for (const Candidate& c : candidates) {
        if (rgb_used[c.rgb] || depth_used[c.depth]) continue;
        rgb_used[c.rgb] = depth_used[c.depth] = true;
        chosen.emplace_back(c.rgb, c.depth);
    }
    std::sort(chosen.begin(), chosen.end(), [&](const auto& x, const auto& y) {
        if (rgb[x.first].stamp_ns != rgb[y.first].stamp_ns) {
            return rgb[x.first].stamp_ns < rgb[y.first].stamp_ns;
        }
        return x < y;
    });
    pairs.reserve(chosen.size());
    for (const auto& [r, d] : chosen) pairs.push_back({rgb[r], depth[d]});
    return pairs;
}

TumFolderSource::TumFolderSource(TumFolderConfig config, std::vector<AssociatedPair> pairs,
                                 std::vector<std::string> list_errors)
    : config_(std::move(config)), pairs_(std::move(pairs)), list_errors_(std::move(list_errors)) {}

Result<std::unique_ptr<TumFolderSource>> TumFolderSource::open(const TumFolderConfig& config) {
    if (config.folder.empty()) {
        return error(StatusCode::kInvalidArgument,
                     std::string("no TUM folder given; ") + kExpectedLayout);
    }
    auto window = window_ns(config.max_difference_s, "max_difference_s");
    if (!window) return window.status();
    if (!(std::isfinite(config.depth_units_per_m) && config.depth_units_per_m > 0) ||
        config.max_width <= 0 || config.max_height <= 0 || config.width < 0 || config.height < 0 ||
        config.width > config.max_width || config.height > config.max_height) {
        return error(StatusCode::kInvalidArgument,
                     "TUM folder config needs depth_units_per_m > 0 (finite), a positive max "
                     "size and an image size (width, height) within it; found depth_units_per_m " +
                         number(config.depth_units_per_m) + ", size " +
                         std::to_string(config.width) + "x" + std::to_string(config.height) +
                         ", max " + std::to_string(config.max_width) + "x" +
                         std::to_string(config.max_height));
    }
    const fs::path folder(config.folder);
    std::error_code ec;
    if (!fs::exists(folder, ec)) {
        return error(StatusCode::kNotFound,
                     "TUM folder " + config.folder + " does not exist; " + kExpectedLayout);
    }
    if (!fs::is_directory(folder, ec)) {
        return error(StatusCode::kNotFound, config.folder + " is not a folder; " + kExpectedLayout);
    }
    fs::directory_iterator probe(folder, ec);
    if (ec) {
        return error(StatusCode::kNotFound,
                     "cannot read TUM folder " + config.folder + " (" + ec.message() + ")");
    }

    const std::string associations_file = (folder / "associations.txt").string();
    const std::string rgb_file = (folder / "rgb.txt").string();
    const std::string depth_file = (folder / "depth.txt").string();
    const bool use_associations = config.use_associations_file && fs::exists(associations_file, ec);

    std::vector<AssociatedPair> pairs;
    std::vector<std::string> errors;
    std::string found;  // what the lists held, for the "no frames" message
    if (use_associations) {
        auto parsed = parse_associations(associations_file);
        if (!parsed) return parsed.status();
        errors = std::move(parsed->errors);
        // A pair is one instant: stamps further apart than the association window are refused
        // as associate.py would never have paired them.
        for (AssociatedPair& pair : parsed->pairs) {
            const int64_t apart = std::llabs(pair.rgb.stamp_ns - pair.depth.stamp_ns);
            if (apart <= *window) {
                pairs.push_back(std::move(pair));
                continue;
            }
            std::ostringstream s;
            s << at(associations_file, pair.rgb.line) << ": rgb and depth stamps are "
              << static_cast<double>(apart) * 1e-9 << " s apart, more than max_difference_s ("
              << config.max_difference_s << " s)";
            errors.push_back(s.str());
        }
        found = "associations.txt has no valid line";
    } else {
        for (const std::string& file : {rgb_file, depth_file}) {
            if (!fs::exists(file, ec)) {
                return error(StatusCode::kNotFound, "TUM folder " + config.folder + " has no " +
                                                        fs::path(file).filename().string() + "; " +
                                                        kExpectedLayout);
            }
        }
        auto rgb = parse_stamp_list(rgb_file);
        if (!rgb) return rgb.status();
        auto depth = parse_stamp_list(depth_file);
        if (!depth) return depth.status();
        pairs = associate(rgb->entries, depth->entries, *window);
        errors = std::move(rgb->errors);
        errors.insert(errors.end(), depth->errors.begin(), depth->errors.end());
        std::ostringstream s;
        s << "rgb.txt has " << rgb->entries.size() << " valid lines and depth.txt "
          << depth->entries.size() << ", but no rgb and depth stamps are less than "
          << config.max_difference_s << " s apart";
        found = s.str();
    }
    if (pairs.empty()) {
        std::string message = "no frames in TUM folder " + config.folder + ": " + found;
        if (!errors.empty()) {
            message += " (" + malformed_lines(errors.size()) + "; first: " + errors.front() + ")";
        }
        return error(StatusCode::kInvalidArgument, message);
    }

    // The image size: given, or the first rgb image's (read from its header); the intrinsics
    // must fit it.
    TumFolderConfig checked = config;
    std::string size_from = "the configured image size";
    if (checked.width == 0 || checked.height == 0) {
        const std::string first = (folder / pairs.front().rgb.path).string();
        auto header = read_image_header(first);
        if (header && header->width <= config.max_width && header->height <= config.max_height) {
            checked.width = header->width;
            checked.height = header->height;
            size_from = "the first rgb image " + first;
        }
    }
    const int check_w = checked.width > 0 ? checked.width : config.max_width;
    const int check_h = checked.height > 0 ? checked.height : config.max_height;
    DF_RETURN_IF_ERROR(check_intrinsics(config.intrinsics, check_w, check_h,
                                        "intrinsics for TUM folder " + config.folder + " (size " +
                                            std::to_string(check_w) + "x" +
                                            std::to_string(check_h) + " from " + size_from + ")"));

    std::unique_ptr<TumFolderSource> source(
        new TumFolderSource(checked, std::move(pairs), std::move(errors)));
    source->from_associations_file_ = use_associations;
    return source;
}

std::string TumFolderSource::describe() const {
    std::ostringstream s;
    s << "TUM folder " << config_.folder << " (" << pairs_.size() << " frames, ";
    if (from_associations_file_) {
        s << "associations.txt";
    } else {
        s << "rgb.txt + depth.txt associated within " << config_.max_difference_s << " s";
    }
    if (!list_errors_.empty()) s << ", " << malformed_lines(list_errors_.size()) << " skipped";
    s << ")";
    return s.str();
}

FrameRead TumFolderSource::next() {
    FrameRead read;
    if (cursor_ >= pairs_.size()) {
        read.kind = FrameRead::Kind::kEnd;
        return read;
    }
    const size_t index = cursor_++;
    const AssociatedPair& pair = pairs_[index];
    const fs::path folder(config_.folder);
    const std::string rgb_path = (folder / pair.rgb.path).string();
    const std::string depth_path = (folder / pair.depth.path).string();
    const std::string rgb_list = from_associations_file_ ? "associations.txt" : "rgb.txt";
    const std::string depth_list = from_associations_file_ ? "associations.txt" : "depth.txt";
    const std::string rgb_where =
        "rgb image " + rgb_path + " (" + at(rgb_list, pair.rgb.line) + ")";
    const std::string depth_where =
        "depth image " + depth_path + " (" + at(depth_list, pair.depth.line) + ")";

    auto bad = [&](const std::string& where, const std::string& what) {
        read.kind = FrameRead::Kind::kBadFrame;
        read.error = "frame " + std::to_string(index) + ": " + where + ": " + what;
        return read;
    };
    const SizeRule size{config_.max_width, config_.max_height, config_.width, config_.height};
    auto rgb = load_rgb(rgb_path, size);
    if (!rgb) return bad(rgb_where, rgb.status().message());
    auto depth = load_depth(depth_path, size);
    if (!depth) return bad(depth_where, depth.status().message());
    if (depth->size() != rgb->size()) {
        return bad(depth_where, "image is " + size_name(*depth) + " but rgb image " + rgb_path +
                                    " is " + size_name(*rgb));
    }
    if (config_.depth_invalid_value > 0) {
        depth->setTo(0, *depth >= config_.depth_invalid_value);
    }

    if (config_.width == 0 || config_.height == 0) {  // the first frame fixes the size
        config_.width = rgb->cols;
        config_.height = rgb->rows;
    }
    read.kind = FrameRead::Kind::kFrame;
    RgbdImage& image = read.image;
    image.rgb = std::move(*rgb);
    image.depth = std::move(*depth);
    image.depth_units_per_m = config_.depth_units_per_m;
    image.intrinsics = config_.intrinsics;
    image.sensor_ns = pair.rgb.stamp_ns;
    image.index = index;
    image.rgb_path = rgb_path;
    image.depth_path = depth_path;
    return read;
}

}  // namespace df::io
