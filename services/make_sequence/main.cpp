// df_make_sequence: renders a synthetic RGB-D sequence of a preset with all its ground truth
// (docs/sequence_format.md, docs/sequences.md).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "core/progress.hpp"
#include "sim/sensor.hpp"
#include "sim/sequence.hpp"
#include "sim/writer.hpp"

int main(int argc, char** argv) {
    df::log::set_component("make_sequence");
    CLI::App app{
        "Renders a synthetic RGB-D sequence with ground truth (TUM layout + instances, "
        "object trajectories and models)"};
    std::string preset = "default", out;
    df::sim::PresetOptions options;
    bool no_noise = false, list = false, no_models = false;
    int threads = 0;
    app.add_option("--preset", preset, "preset name (--list-presets)")->capture_default_str();
    app.add_option("--out", out, "output folder (new, empty, or an earlier output)");
    app.add_option("--frames", options.frames, "number of frames at 30 Hz (0: preset default)")
        ->check(CLI::Range(0, 100000));
    app.add_option("--seed", options.seed, "seed of textures, colours and noise")
        ->capture_default_str();
    app.add_option("--width", options.width, "image width")
        ->capture_default_str()
        ->check(CLI::Range(16, 4096));
    app.add_option("--height", options.height, "image height")
        ->capture_default_str()
        ->check(CLI::Range(12, 4096));
    app.add_flag("--no-noise", no_noise, "ideal sensor: exact depth and colour, no holes");
    std::vector<std::string> effects_off;
    std::string effect_names;
    for (const std::string& e : df::sim::sensor_effects())
        effect_names += (effect_names.empty() ? "" : ", ") + e;
    app.add_option("--sensor-off", effects_off,
                   "sensor effects to switch off (" + effect_names + ")")
        ->delimiter(',');
    app.add_flag("--no-models", no_models, "skip models/*.ply");
    app.add_option("--threads", threads, "worker threads (0: all cores; output is the same)")
        ->check(CLI::Range(0, 256));
    app.add_option("--photos", options.photo_folder, "folder of the darknet sample photos")
        ->capture_default_str();
    app.add_flag("--list-presets", list, "print the presets and exit");
    CLI11_PARSE(app, argc, argv);

    if (list) {
        for (const auto& p : df::sim::presets())
            std::printf("%-20s %4d frames  %s\n", p.name.c_str(), p.default_frames,
                        p.summary.c_str());
        return 0;
    }
    if (out.empty()) {
        df::log::error("--out is required (the folder to write the sequence to)");
        return 2;
    }
    options.noise = !no_noise;
    auto sequence = df::sim::make_sequence(preset, options);
    if (!sequence) {
        df::log::error(sequence.status().to_string());
        return 2;
    }
    for (const std::string& effect : effects_off) {
        if (!df::sim::set_sensor_effect(&sequence->sensor, effect, false)) {
            std::string known;
            for (const auto& e : df::sim::sensor_effects())
                known += (known.empty() ? "" : ", ") + e;
            df::log::error("--sensor-off: unknown effect '", effect, "' (known: ", known, ")");
            return 2;
        }
    }
    for (const std::string& name : sequence->missing_photos)
        df::log::warn("photo ", options.photo_folder, "/", name,
                      ".jpg not readable: its decals are grey");
    df::log::info("preset ", sequence->preset, ": ", sequence->frames, " frames ", sequence->width,
                  "x", sequence->height, ", seed ", sequence->seed, ", ",
                  sequence->scene.objects.size(), " moving objects, noise ",
                  no_noise ? "off" : "on", " -> ", out);
    df::sim::WriteOptions write;
    write.threads = threads;
    write.models = !no_models;
    df::Progress progress("frames rendered", sequence->frames, 50);
    write.progress = [&progress](int done, int) { progress.update(done); };
    const auto t0 = std::chrono::steady_clock::now();
    df::Result<df::sim::WriteReport> report =
        df::error(df::StatusCode::kInternal, "write_sequence did not run");
    try {
        report = df::sim::write_sequence(*sequence, out, write);
    } catch (const std::exception& e) {  // OpenCV (cv::Exception), allocation failures
        df::log::error("writing ", out, " failed: ", e.what());
        return 1;
    }
    if (!report) {
        df::log::error(report.status().to_string());
        return 1;
    }
    progress.finish();
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    df::log::info("wrote ", sequence->frames, " frames to ", out, " in ", total, " s (frames ",
                  report->frames_s, " s = ", sequence->frames / report->frames_s,
                  " frames/s; models ", report->models_s, " s)");
    return 0;
}
