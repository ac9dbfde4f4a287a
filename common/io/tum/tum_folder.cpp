#include "io/tum/tum_folder.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>

#include "io/tum/image_text.hpp"

namespace df::io {
namespace fs = std::filesystem;

namespace detail {

const char* depth_name(int cv_depth) {
    switch (cv_depth) {
        case CV_8U:
            return "8-bit";
        case CV_8S:
            return "8-bit signed";
        case CV_16U:
            return "16-bit";
        case CV_16S:
            return "16-bit signed";
        case CV_32S:
            return "32-bit integer";
        case CV_32F:
            return "32-bit float";
        case CV_64F:
            return "64-bit float";
        default:
            return "unknown";
    }
}

/// e.g. "8-bit 1-channel".
std::string type_name(const cv::Mat& m) {
    return std::string(depth_name(m.depth())) + " " + std::to_string(m.channels()) + "-channel";
}

std::string size_name(const cv::Mat& m) {
    return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

}  // namespace detail

using detail::size_name;
using detail::type_name;

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
bool parse_stamped_path(const TumTextLine& line, size_t first, StampedPath* out,
                        std::string* what) {
    if (!parse_tum_stamp(line.fields[first], &out->stamp_s)) {
        *what = "expected a time stamp in seconds (a non-negative number), found " +
                quote(line.fields[first]);
        return false;
    }
    out->path = line.fields[first + 1];
    out->line = line.line;
    return true;
}

/// Reads an image, turning both a missing file and an undecodable one into a message.
Result<cv::Mat> read_image(const std::string& path, int flags) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        return error(StatusCode::kNotFound,
                     fs::exists(path, ec) ? "is not a file" : "file does not exist");
    }
    cv::Mat image;
    try {
        image = cv::imread(path, flags);
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, std::string("cannot decode image: ") + e.what());
    }
    if (image.empty()) {
        return error(StatusCode::kIoError,
                     "cannot decode image (corrupt, truncated or not an image file)");
    }
    return image;
}

/// Converts what imread returned to CV_8UC3 in R,G,B order, or says why it cannot.
Result<cv::Mat> to_rgb(const cv::Mat& raw) {
    if (raw.depth() != CV_8U) {
        return error(StatusCode::kInvalidArgument,
                     "expected an 8-bit colour image, found " + type_name(raw));
    }
    int code = -1;
    switch (raw.channels()) {
        case 1:
            code = cv::COLOR_GRAY2RGB;
            break;
        case 3:
            code = cv::COLOR_BGR2RGB;
            break;
        case 4:
            code = cv::COLOR_BGRA2RGB;
            break;
        default:
            return error(StatusCode::kInvalidArgument,
                         "expected an 8-bit colour image, found " + type_name(raw));
    }
    cv::Mat rgb;
    cv::cvtColor(raw, rgb, code);
    return rgb;
}

Status check_size(const cv::Mat& image, int max_width, int max_height) {
    if (image.cols <= max_width && image.rows <= max_height) return Status::ok();
    return error(StatusCode::kInvalidArgument,
                 "image is " + size_name(image) + ", larger than the " + std::to_string(max_width) +
                     "x" + std::to_string(max_height) + " maximum");
}

/// Reads a colour image as CV_8UC3 R,G,B no larger than the maximum, or says what was wrong.
Result<cv::Mat> load_rgb(const std::string& path, int max_width, int max_height) {
    auto raw = read_image(path, cv::IMREAD_UNCHANGED);
    if (!raw) return raw.status();
    auto rgb = to_rgb(*raw);
    if (!rgb) return rgb.status();
    DF_RETURN_IF_ERROR(check_size(*rgb, max_width, max_height));
    return rgb;
}

/// Reads a depth image as CV_16UC1 no larger than the maximum, or says what was wrong.
Result<cv::Mat> load_depth(const std::string& path, int max_width, int max_height) {
    auto depth = read_image(path, cv::IMREAD_UNCHANGED);
    if (!depth) return depth.status();
    if (depth->type() != CV_16UC1) {
        return error(StatusCode::kInvalidArgument,
                     "expected a 16-bit 1-channel depth image, found " + type_name(*depth));
    }
    DF_RETURN_IF_ERROR(check_size(*depth, max_width, max_height));
    return depth;
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
    if (field.empty()) return false;
    const char* begin = field.c_str();
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(begin, &end);
    if (end != begin + field.size() || errno == ERANGE) return false;
    if (!std::isfinite(value) || value < 0) return false;
    *stamp_s = value;
    return true;
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
    for (const TumTextLine& line : *lines) {
        // TUM's tools read the first two fields and ignore any after them; so do we.
        std::string what;
        StampedPath entry;
        if (line.fields.size() < 2) {
            what = "expected 'timestamp path', found " + quote(line.text);
        } else if (parse_stamped_path(line, 0, &entry, &what)) {
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
    for (const TumTextLine& line : *lines) {
        std::string what;
        AssociatedPair pair;
        if (line.fields.size() < 4) {
            what = "expected 't_rgb rgb_path t_depth depth_path', found " + quote(line.text);
        } else if (parse_stamped_path(line, 0, &pair.rgb, &what) &&
                   parse_stamped_path(line, 2, &pair.depth, &what)) {
            parse.pairs.push_back(std::move(pair));
            continue;
        }
        parse.errors.push_back(at(file, line.line) + ": " + what);
    }
    return parse;
}

std::vector<AssociatedPair> associate(const std::vector<StampedPath>& rgb,
                                      const std::vector<StampedPath>& depth,
                                      double max_difference_s) {
    std::vector<AssociatedPair> pairs;
    if (!(max_difference_s > 0) || rgb.empty() || depth.empty()) return pairs;

    // Candidates are found through the depth stamps in sorted order, so the cost stays
    // O((n + m) log m + candidates) instead of associate.py's all-pairs loop.
    std::vector<size_t> depth_order(depth.size());
    std::iota(depth_order.begin(), depth_order.end(), size_t{0});
    std::stable_sort(depth_order.begin(), depth_order.end(),
                     [&](size_t a, size_t b) { return depth[a].stamp_s < depth[b].stamp_s; });

    struct Candidate {
        double difference;
        size_t rgb, depth;
    };
    std::vector<Candidate> candidates;
    for (size_t r = 0; r < rgb.size(); ++r) {
        const double a = rgb[r].stamp_s;
        auto it = std::lower_bound(depth_order.begin(), depth_order.end(), a - max_difference_s,
                                   [&](size_t d, double v) { return depth[d].stamp_s < v; });
        for (; it != depth_order.end() && depth[*it].stamp_s < a + max_difference_s; ++it) {
            const double difference = std::abs(a - depth[*it].stamp_s);
            if (difference < max_difference_s) candidates.push_back({difference, r, *it});
        }
    }
    // associate.py sorts (difference, t_rgb, t_depth) tuples; list positions break exact ties.
    std::sort(candidates.begin(), candidates.end(), [&](const Candidate& x, const Candidate& y) {
        if (x.difference != y.difference) return x.difference < y.difference;
        if (rgb[x.rgb].stamp_s != rgb[y.rgb].stamp_s)
            return rgb[x.rgb].stamp_s < rgb[y.rgb].stamp_s;
        if (depth[x.depth].stamp_s != depth[y.depth].stamp_s) {
            return depth[x.depth].stamp_s < depth[y.depth].stamp_s;
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
        if (rgb[x.first].stamp_s != rgb[y.first].stamp_s) {
            return rgb[x.first].stamp_s < rgb[y.first].stamp_s;
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
    if (!(config.max_difference_s > 0) || !(config.depth_units_per_m > 0) ||
        config.max_width <= 0 || config.max_height <= 0) {
        return error(StatusCode::kInvalidArgument,
                     "TUM folder config needs max_difference_s > 0, depth_units_per_m > 0 and a "
                     "positive max size");
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
        pairs = std::move(parsed->pairs);
        errors = std::move(parsed->errors);
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
        pairs = associate(rgb->entries, depth->entries, config.max_difference_s);
        errors = std::move(rgb->errors);
        errors.insert(errors.end(), depth->errors.begin(), depth->errors.end());
        std::ostringstream s;
        s << "rgb.txt has " << rgb->entries.size() << " valid lines and depth.txt "
          << depth->entries.size() << ", but no rgb and depth stamps are within "
          << config.max_difference_s << " s of each other";
        found = s.str();
    }
    if (pairs.empty()) {
        std::string message = "no frames in TUM folder " + config.folder + ": " + found;
        if (!errors.empty()) {
            message += " (" + malformed_lines(errors.size()) + "; first: " + errors.front() + ")";
        }
        return error(StatusCode::kInvalidArgument, message);
    }

    std::unique_ptr<TumFolderSource> source(
        new TumFolderSource(config, std::move(pairs), std::move(errors)));
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
    auto rgb = load_rgb(rgb_path, config_.max_width, config_.max_height);
    if (!rgb) return bad(rgb_where, rgb.status().message());
    auto depth = load_depth(depth_path, config_.max_width, config_.max_height);
    if (!depth) return bad(depth_where, depth.status().message());
    if (depth->size() != rgb->size()) {
        return bad(depth_where, "image is " + size_name(*depth) + " but rgb image " + rgb_path +
                                    " is " + size_name(*rgb));
    }
    if (config_.depth_invalid_value > 0) {
        depth->setTo(0, *depth >= config_.depth_invalid_value);
    }

    read.kind = FrameRead::Kind::kFrame;
    RgbdImage& image = read.image;
    image.rgb = std::move(*rgb);
    image.depth = std::move(*depth);
    image.depth_units_per_m = config_.depth_units_per_m;
    image.intrinsics = config_.intrinsics;
    image.sensor_ns = std::llround(pair.rgb.stamp_s * 1e9);
    image.index = index;
    image.rgb_path = rgb_path;
    image.depth_path = depth_path;
    return read;
}

}  // namespace df::io
