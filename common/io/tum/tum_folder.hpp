#pragma once
/// Reading RGB-D sequences in the TUM RGB-D layout:
///   <folder>/rgb.txt, depth.txt       lines "timestamp path", '#' comments
///   <folder>/associations.txt         optional, lines "t_rgb rgb_path t_depth depth_path"
///   rgb/*.png (8-bit colour; JPEG accepted too), depth/*.png (16-bit, units per metre
///   configurable)
/// Associating rgb and depth stamps follows TUM's associate.py: all pairs within max_difference,
/// taken greedily by smallest |t_rgb - t_depth|, one to one, then sorted by rgb stamp.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "io/tum/stamp.hpp"

namespace df::io {

/// Intrinsics presets of the TUM RGB-D benchmark (fr1, fr2, fr3) and of the 7-Scenes data.
/// Returns kInvalidArgument naming the known presets for an unknown name.
Result<Intrinsics> intrinsics_preset(const std::string& name);

/// One frame from two picture files (e.g. a TUM folder's rgb/<stamp>.png and depth/<stamp>.png):
/// depth 16-bit 1-channel in raw units (depth_units_per_m per metre), colour 8-bit (grey, B,G,R or
/// B,G,R,A; returned R,G,B) of the depth's size, at most kMaxWidth x kMaxHeight. An empty `color`
/// gives a grey colour image. Errors start with the file's path and say what was wrong.
Result<RgbdImage> read_rgbd_files(const std::string& color, const std::string& depth,
                                  const Intrinsics& intrinsics, double depth_units_per_m);

struct TumFolderConfig {
    std::string folder;
    Intrinsics intrinsics;              ///< pixels
    double depth_units_per_m = 5000.0;  ///< TUM: 5000; 7-Scenes/OpenNI: 1000
    int depth_invalid_value = 0;        ///< raw values >= this (if > 0) become 0 (7-Scenes: 65535)
    double max_difference_s = 0.02;     ///< association window, (0, 1e6] s
    bool use_associations_file = true;  ///< use associations.txt when the folder has one
    int max_width = kMaxWidth, max_height = kMaxHeight;
    /// The size every image must have (the intrinsics' image size), checked from the file's
    /// header before it is decoded; 0 = the size of the first pair's rgb image.
    int width = 0, height = 0;
};

/// One line of a "timestamp path" list.
struct StampedPath {
    int64_t stamp_ns = 0;  ///< exact (stamp.hpp), from the list's text
    std::string path;      ///< relative to the folder, as written
    int line = 0;          ///< 1-based line in the list file, for messages
};

struct ListParse {
    std::vector<StampedPath> entries;
    std::vector<std::string> errors;  ///< "<file>:<line>: <what was wrong>" for each malformed line
};

/// Parses a "timestamp path" list (rgb.txt, depth.txt); stamps by stamp.hpp's rules, each bad
/// one listed in `errors` with file and line. Fails only if the file cannot be read.
Result<ListParse> parse_stamp_list(const std::string& file);

struct AssociatedPair {
    StampedPath rgb, depth;
};

/// TUM associate.py: greedy one-to-one by |t_rgb - t_depth| < max_difference_ns (integer
/// nanoseconds, so identical stamps always pair), sorted by rgb stamp.
std::vector<AssociatedPair> associate(const std::vector<StampedPath>& rgb,
                                      const std::vector<StampedPath>& depth,
                                      int64_t max_difference_ns);

struct AssociationsParse {
    std::vector<AssociatedPair> pairs;
    std::vector<std::string> errors;  ///< "<file>:<line>: ..." per malformed line
};
/// Parses associations.txt ("t_rgb rgb_path t_depth depth_path").
Result<AssociationsParse> parse_associations(const std::string& file);

/// A TUM folder as a frame source. open() fails with a clear message if the folder or its lists
/// cannot be read or no frame pairs are found; malformed lines are logged at open() and counted.
/// next() reports a missing/corrupt/wrong-size image as kBadFrame (naming the file) and moves on.
class TumFolderSource : public FrameSource {
  public:
    static Result<std::unique_ptr<TumFolderSource>> open(const TumFolderConfig& config);

    FrameRead next() override;
    int64_t size() const override { return static_cast<int64_t>(pairs_.size()); }
    std::string describe() const override;

    /// Malformed list lines found at open(), each "<file>:<line>: ...".
    const std::vector<std::string>& list_errors() const { return list_errors_; }
    const std::vector<AssociatedPair>& pairs() const { return pairs_; }
    /// Rewinds to the first frame (for looping playback).
    void rewind() { cursor_ = 0; }
    /// The next frame read is pairs()[index] (the end for index >= size()).
    void seek(size_t index) { cursor_ = index < pairs_.size() ? index : pairs_.size(); }

  private:
    TumFolderSource(TumFolderConfig config, std::vector<AssociatedPair> pairs,
                    std::vector<std::string> list_errors);
    TumFolderConfig config_;
    std::vector<AssociatedPair> pairs_;
    std::vector<std::string> list_errors_;
    size_t cursor_ = 0;
    bool from_associations_file_ = false;  ///< pairs came from associations.txt (for messages)
};

/// One data line of a TUM text file (rgb.txt, associations.txt, groundtruth.txt): blank lines and
/// '#' comments are dropped; fields are separated by spaces, tabs or commas, as in TUM's tools.
struct TumTextLine {
    int line = 0;      ///< 1-based line number in the file
    std::string text;  ///< the line as written, without its line ending
    std::vector<std::string> fields;
};

/// Reads the data lines of a TUM text file. kNotFound if the file does not exist, kIoError if it
/// cannot be read (or is a folder).
Result<std::vector<TumTextLine>> read_tum_text_lines(const std::string& file);

/// Parses a TUM time stamp field by stamp.hpp's rules into seconds (the double nearest the exact
/// value). False for a stamp those rules refuse. Prefer parse_stamp (exact nanoseconds).
bool parse_tum_stamp(const std::string& field, double* stamp_s);

/// Checks pinhole intrinsics against the image size they are for: fx, fy finite and in
/// [0.05, 20] x width (fields of view between about 3 and 170 degrees), cx in [0, width],
/// cy in [0, height]. kInvalidArgument naming `where`, the field, its value and the range.
Status check_intrinsics(const Intrinsics& intrinsics, int width, int height,
                        const std::string& where);

/// Writes a TUM folder (rgb/, depth/, rgb.txt, depth.txt, associations.txt) from frames.
/// Used by tests and by the built-in default data. Images are PNG.
/// Each frame needs rgb CV_8UC3 (R,G,B order) and depth CV_16UC1 of the same size and a distinct
/// sensor_ns >= 0; files are named by that stamp in seconds (stamp_text: 6 decimals, microseconds)
/// and rgb and depth share the stamp. Creates the folders as needed and overwrites existing files.
Status write_tum_folder(const std::string& folder, const std::vector<RgbdImage>& frames);

}  // namespace df::io
