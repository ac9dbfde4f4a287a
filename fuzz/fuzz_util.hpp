#pragma once
/// What the fuzz targets share: the input as a file (for readers that take a path), and a check
/// that aborts, so that a broken property is a crash libFuzzer reports and keeps.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace df::fuzz {

/// Writes the input to this process's scratch file and returns its path (one file per process
/// and target, rewritten on each run; libFuzzer's -jobs runs use other processes).
inline std::string as_file(const char* target, const uint8_t* data, size_t size,
                           const char* suffix = "") {
    const char* dir = std::getenv("TMPDIR");
    const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/df_fuzz_" + target + "_" +
                             std::to_string(::getpid()) + suffix;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    return path;
}

}  // namespace df::fuzz

/// A property every input must keep; otherwise the input is a finding.
#define DF_FUZZ_CHECK(cond)                                                                  \
    do {                                                                                     \
        if (!(cond)) {                                                                       \
            std::fprintf(stderr, "%s:%d: property broken: %s\n", __FILE__, __LINE__, #cond); \
            std::abort();                                                                    \
        }                                                                                    \
    } while (0)
