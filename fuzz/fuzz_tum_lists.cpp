// TUM text input: one stamp field (parse_stamp, parse_tum_stamp) and whole list files
// (parse_stamp_list for rgb.txt/depth.txt, parse_associations for associations.txt), then the
// association of the parsed lists. Properties: an accepted stamp in seconds prints back
// (stamp_text) to the same nanoseconds; parsed entries name lines of the file; associate()
// pairs each entry at most once, within the window.
#include <set>
#include <string>

#include "fuzz_util.hpp"
#include "io/tum/stamp.hpp"
#include "io/tum/tum_folder.hpp"

using namespace df;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // The first line as one stamp field.
    const std::string field = text.substr(0, text.find('\n'));
    auto stamp = io::parse_stamp(field);
    double seconds = 0;
    DF_FUZZ_CHECK(io::parse_tum_stamp(field, &seconds) == stamp.is_ok());
    if (stamp) {
        DF_FUZZ_CHECK(stamp->ns >= 0);
        auto back = io::parse_stamp(io::stamp_text(stamp->ns, 9));
        DF_FUZZ_CHECK(back.is_ok() && back->ns == stamp->ns);
    }
    size_t lines = 1;
    for (char c : text) lines += c == '\n';

    const std::string path = fuzz::as_file("tum_lists", data, size, ".txt");
    auto list = io::parse_stamp_list(path);
    DF_FUZZ_CHECK(list.is_ok());
    for (const io::StampedPath& e : list->entries) {
        DF_FUZZ_CHECK(e.line >= 1 && static_cast<size_t>(e.line) <= lines);
        DF_FUZZ_CHECK(e.stamp_ns >= 0);
    }
    auto assoc = io::parse_associations(path);
    DF_FUZZ_CHECK(assoc.is_ok());

    const int64_t window = 20'000'000;
    const auto pairs = io::associate(list->entries, list->entries, window);
    std::set<int> used_rgb, used_depth;
    for (const io::AssociatedPair& p : pairs) {
        DF_FUZZ_CHECK(used_rgb.insert(p.rgb.line).second);
        DF_FUZZ_CHECK(used_depth.insert(p.depth.line).second);
        const int64_t d = p.rgb.stamp_ns - p.depth.stamp_ns;
        DF_FUZZ_CHECK(d < window && -d < window);
    }
    return 0;
}
