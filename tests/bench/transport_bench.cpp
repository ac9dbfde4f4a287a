// df_bench_transport: one-way latency and CPU of 640x480 RGB-D frames between processes,
// loaned shared memory vs copied shared memory vs UDP loopback, 1 and 3 readers, 30 Hz and
// flat out. Latency = reader's wake-up time minus the writer's clock just before dds_write().
// Run through tests/bench/run_transport_bench.sh (it starts RouDi).
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/log.hpp"
#include "dds/msg_convert.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"

namespace {

using namespace df;

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

double pct(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

dds::Transport transport_of(const std::string& mode) {
    return mode == "udp" ? dds::Transport::kUdp : dds::Transport::kSharedMemory;
}

/// Reader process: prints "received p50_ms p99_ms cpu_ms_per_frame".
int run_reader(const std::string& mode, const std::string& topic, int count) {
    dds::ParticipantConfig pc;
    pc.transport = transport_of(mode);
    auto p = dds::Participant::create(pc);
    if (!p) return 1;
    auto r = dds::Reader<df_msg_RgbdFrame>::create(*p, topic, {dds::QosProfile::kFrames, 16});
    auto ws = dds::WaitSet::create(*p);
    if (!r || !ws || !ws->attach_reader(r->get())) {
        std::fprintf(stderr, "reader set-up failed on %s\n", topic.c_str());
        return 1;
    }
    std::vector<double> lat;
    const double cpu0 = cpu_seconds();
    auto last = std::chrono::steady_clock::now();
    uint64_t checksum = 0;
    while (static_cast<int>(lat.size()) < count) {
        (void)ws->wait(DDS_MSECS(100));
        const auto n = r->take([&](const df_msg_RgbdFrame& f, const dds_sample_info_t&) {
            lat.push_back(
                (static_cast<double>(dds::wall_ns()) - static_cast<double>(f.header.capture_ns)) *
                1e-6);
            checksum +=
                f.rgb[f.header.seq % 1000] + f.depth[f.header.seq % 1000];  // touch the data
        });
        if (n && *n > 0) last = std::chrono::steady_clock::now();
        if (!lat.empty() && std::chrono::steady_clock::now() - last > std::chrono::seconds(2))
            break;
    }
    const double cpu = cpu_seconds() - cpu0;
    std::printf("%zu %.4f %.4f %.4f %llu\n", lat.size(), pct(lat, 0.5), pct(lat, 0.99),
                lat.empty() ? 0 : cpu * 1e3 / lat.size(),
                static_cast<unsigned long long>(checksum % 7));
    return 0;
}

struct Row {
    std::string mode;
    int readers = 0;
    double rate_hz = 0;
    int sent = 0;
    double writer_cpu_ms = 0;
    std::vector<std::vector<double>> reader_stats;  // received, p50, p99, cpu
};

Row run_writer(const std::string& self, const std::string& mode, int readers, double rate_hz,
               int frames) {
    Row row{mode, readers, rate_hz, frames, 0, {}};
    std::string safe_mode = mode;  // topic names allow letters, digits, '_' and '/'
    std::replace(safe_mode.begin(), safe_mode.end(), '-', '_');
    const std::string topic = "bench" + std::to_string(getpid()) + "_" + safe_mode +
                              std::to_string(readers) + "_" +
                              std::to_string(static_cast<int>(rate_hz)) + "/frames";
    std::vector<FILE*> procs;
    for (int i = 0; i < readers; ++i) {
        const std::string cmd = self + " --role reader --mode " + mode + " --topic " + topic +
                                " --frames " + std::to_string(frames) + " 2>/dev/null";
        procs.push_back(popen(cmd.c_str(), "r"));
    }
    dds::ParticipantConfig pc;
    pc.transport = transport_of(mode);
    auto p = dds::Participant::create(pc);
    dds::EndpointOptions eo{dds::QosProfile::kFrames};
    eo.allow_loans = mode == "shm-loan";
    auto w = dds::Writer<df_msg_RgbdFrame>::create(*p, topic, eo);
    if (!p || !w) return row;
    (void)dds::wait_for_matches(w->get(), true, static_cast<uint32_t>(readers), DDS_SECS(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    io::RgbdImage img;
    img.rgb = cv::Mat(480, 640, CV_8UC3);
    img.depth = cv::Mat(480, 640, CV_16UC1);
    cv::randu(img.rgb, 0, 256);
    cv::randu(img.depth, 0, 20000);
    const double cpu0 = cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        if (rate_hz > 0)
            std::this_thread::sleep_until(start + std::chrono::duration<double>(i / rate_hz));
        auto loan = w->loan();
        if (!loan) continue;
        df_msg_Header h{};
        h.seq = static_cast<uint64_t>(i);
        dds::fill_frame(img, h, loan->get());
        (*loan)->header.capture_ns = dds::wall_ns();
        (void)w->write(std::move(*loan));
    }
    row.writer_cpu_ms = (cpu_seconds() - cpu0) * 1e3 / frames;
    for (FILE* f : procs) {
        double n = 0, p50 = 0, p99 = 0, cpu = 0;
        unsigned long long ck = 0;
        if (fscanf(f, "%lf %lf %lf %lf %llu", &n, &p50, &p99, &cpu, &ck) == 5)
            row.reader_stats.push_back({n, p50, p99, cpu});
        pclose(f);
    }
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"df_bench_transport"};
    std::string role = "main", mode = "shm-loan", topic;
    int frames = 300;
    double flat_frames = 600;
    app.add_option("--role", role);
    app.add_option("--mode", mode);
    app.add_option("--topic", topic);
    app.add_option("--frames", frames, "frames per 30 Hz run")->default_val(300);
    app.add_option("--flat-frames", flat_frames, "frames per flat-out run")->default_val(600);
    CLI11_PARSE(app, argc, argv);
    df::log::set_level(df::log::Level::kWarn);
    if (role == "reader") return run_reader(mode, topic, frames);

    char self[4096] = {};
    const ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) return 1;
    std::printf(
        "640x480 RGB-D frames (%zu bytes per sample), one writer process, reader processes on this "
        "host\n",
        sizeof(df_msg_RgbdFrame));
    std::printf("%-9s %7s %8s %7s %9s %9s %9s %13s %13s\n", "path", "readers", "rate", "sent",
                "received", "p50 ms", "p99 ms", "writer cpu/f", "reader cpu/f");
    for (const double rate : {30.0, 0.0}) {
        for (const int readers : {1, 3}) {
            for (const std::string m : {"shm-loan", "shm-copy", "udp"}) {
                const int n = rate > 0 ? frames : static_cast<int>(flat_frames);
                const Row r = run_writer(self, m, readers, rate, n);
                double recv = 0, p50 = 0, p99 = 0, cpu = 0;
                for (const auto& s : r.reader_stats) {
                    recv += s[0];
                    p50 = std::max(p50, s[1]);
                    p99 = std::max(p99, s[2]);
                    cpu += s[3] / r.reader_stats.size();
                }
                std::printf("%-9s %7d %8s %7d %9.0f %9.3f %9.3f %10.3f ms %10.3f ms\n", m.c_str(),
                            readers, rate > 0 ? "30 Hz" : "flat out", r.sent, recv, p50, p99,
                            r.writer_cpu_ms, cpu);
                std::fflush(stdout);
            }
        }
    }
    std::printf("p50/p99: worst reader; received: sum over readers; cpu/f: CPU time per frame\n");
    return 0;
}
