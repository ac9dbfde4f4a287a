// df_bench_sim: how fast df_make_sequence's presets generate (frames per second, 640x480 by
// default): rendering, sensor model, PNG encoding and writing, as the generator does it; and the
// time for the models (PLY). Figures go to docs/sequences.md.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/sequence.hpp"
#include "sim/writer.hpp"

int main(int argc, char** argv) {
    CLI::App app{"Generation speed of the synthetic sequence presets"};
    int frames = 60, width = 640, height = 480, threads = 0;
    std::vector<std::string> names;
    std::string out_dir =
        (std::filesystem::temp_directory_path() / ("df_bench_sim_" + std::to_string(::getpid())))
            .string();
    app.add_option("--frames", frames, "frames per preset")
        ->capture_default_str()
        ->check(CLI::Range(1, 10000));
    app.add_option("--width", width, "image width")->capture_default_str();
    app.add_option("--height", height, "image height")->capture_default_str();
    app.add_option("--threads", threads, "worker threads (0: all cores)")->capture_default_str();
    app.add_option("--presets", names, "presets to measure (default: all)");
    app.add_option("--out-dir", out_dir, "scratch folder (removed afterwards)")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (names.empty())
        for (const auto& p : df::sim::presets()) names.push_back(p.name);

    std::printf("%-20s %7s %10s %12s %10s\n", "preset", "frames", "frames/s", "ms/frame",
                "models s");
    for (const std::string& name : names) {
        df::sim::PresetOptions options;
        options.frames = frames;
        options.width = width;
        options.height = height;
        auto sequence = df::sim::make_sequence(name, options);
        if (!sequence) {
            std::fprintf(stderr, "%s\n", sequence.status().to_string().c_str());
            return 1;
        }
        const std::string folder = out_dir + "/" + name;
        df::sim::WriteOptions write;
        write.threads = threads;
        const auto report = df::sim::write_sequence(*sequence, folder, write);
        std::error_code ec;
        std::filesystem::remove_all(folder, ec);
        if (!report) {
            std::fprintf(stderr, "%s\n", report.status().to_string().c_str());
            return 1;
        }
        std::printf("%-20s %7d %10.1f %12.1f %10.2f\n", name.c_str(), frames,
                    frames / report->frames_s, 1e3 * report->frames_s / frames, report->models_s);
        std::fflush(stdout);
    }
    std::error_code ec;
    std::filesystem::remove_all(out_dir, ec);
    return 0;
}
