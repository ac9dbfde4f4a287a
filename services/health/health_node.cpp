#include "health_node.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/log.hpp"
#include "dds/msg_types.hpp"
#include "dds/reader.hpp"
#include "dds/waitset.hpp"
#include "dds/writer.hpp"
#include "service/service.hpp"

namespace df::health {
namespace {

Status range_error(const std::string& flag, double value, const std::string& range) {
    return Status(StatusCode::kInvalidArgument,
                  "--" + flag + " " + std::to_string(value) + " is out of range " + range);
}

bool in_open_closed(double v, double lo, double hi) {
    return std::isfinite(v) && v > lo && v <= hi;
}

double seconds(int64_t ns) { return static_cast<double>(ns) * 1e-9; }

}  // namespace

Status validate(const HealthConfig& c) {
    if (c.status_path.empty()) {
        return Status(StatusCode::kInvalidArgument, "--status FILE is required");
    }
    if (c.ns.empty()) return Status(StatusCode::kInvalidArgument, "--ns must not be empty");
    if (!in_open_closed(c.period_s, 0.05, 60))
        return range_error("period-s", c.period_s, "(0.05, 60]");
    if (!in_open_closed(c.deadline_s, 0.05, 60)) {
        return range_error("deadline-s", c.deadline_s, "(0.05, 60]");
    }
    if (c.failures < 1 || c.failures > 100) return range_error("failures", c.failures, "[1, 100]");
    if (!in_open_closed(c.write_period_s, 0.01, 10)) {
        return range_error("write-period-s", c.write_period_s, "(0.01, 10]");
    }
    return Status::ok();
}

HealthNode::~HealthNode() {
    stop_.store(true);
    if (!worker_.joinable()) return;
    bool stuck;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stuck = probe_.in_cycle;
    }
    // A worker blocked inside iceoryx never returns: leave it to process exit.
    if (stuck) {
        worker_.detach();
    } else {
        worker_.join();
    }
}

std::string HealthNode::probe_once(uint64_t cycle, double* rtt_ms) {
    // A private topic per process; fresh endpoints every cycle, so RouDi must create and connect
    // new ports: a RouDi that is stopped, dead or deadlocked fails the cycle.
    const std::string topic =
        dds::topic_name(config_.ns, "_health_probe_" + std::to_string(::getpid()));
    const dds::EndpointOptions options{dds::QosProfile::kStatus, 4};
    auto reader = dds::Reader<df_msg_StageStatus>::create(participant_, topic, options);
    if (!reader) return reader.status().message();
    auto writer = dds::Writer<df_msg_StageStatus>::create(participant_, topic, options);
    if (!writer) return writer.status().message();
    if (!writer->loans_shared_memory()) {
        return "the probe writer gets no shared-memory loans (RouDi gone or pools exhausted)";
    }
    auto waitset = dds::WaitSet::create(participant_);
    if (!waitset) return waitset.status().message();
    if (auto s = waitset->attach_reader(reader->get()); !s) return s.message();
    const int64_t start = service::steady_ns();
    const auto deadline = start + static_cast<int64_t>(config_.deadline_s * 1e9);
    // Written again every 100 ms: samples written before iceoryx connects the ports are lost.
    while (service::steady_ns() < deadline && !stop_.load()) {
        auto loan = writer->loan();
        if (!loan) return loan.status().message();
        if (!loan->shared_memory()) return "no shared-memory chunk for the probe sample";
        (*loan)->header.seq = cycle;
        dds::set_name((*loan)->stage, "health-probe");
        const int64_t sent = service::steady_ns();
        if (auto s = writer->write(std::move(*loan)); !s) return s.message();
        (void)waitset->wait(DDS_MSECS(100));
        bool back = false;
        auto taken = reader->take([&](const df_msg_StageStatus& m, const dds_sample_info_t&) {
            if (m.header.seq == cycle) back = true;
        });
        if (!taken) return taken.status().message();
        if (back) {
            *rtt_ms = seconds(service::steady_ns() - sent) * 1e3;
            return "";
        }
    }
    return "the probe sample did not come back over shared memory within " +
           std::to_string(config_.deadline_s) + " s";
}

void HealthNode::probe_loop() {
    uint64_t cycle = 0;
    while (!stop_.load()) {
        const int64_t start = service::steady_ns();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            probe_.in_cycle = true;
            probe_.cycle_start_ns = start;
        }
        double rtt_ms = -1;
        const std::string err = probe_once(++cycle, &rtt_ms);
        const bool late =
            service::steady_ns() - start > static_cast<int64_t>(config_.deadline_s * 1e9);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            probe_.in_cycle = false;
            ++probe_.cycles;
            if (err.empty() && !late) {
                if (probe_.consecutive_failures > 0) {
                    log::warn("RouDi probe: shared memory works again after ",
                              probe_.consecutive_failures, " failed cycles");
                }
                ++probe_.ok;
                probe_.consecutive_failures = 0;
                probe_.last_rtt_ms = rtt_ms;
            } else {
                ++probe_.consecutive_failures;
                probe_.last_error =
                    err.empty() ? "the probe cycle took longer than the deadline" : err;
                log::warn("RouDi probe cycle ", cycle, " failed (", probe_.consecutive_failures,
                          " in a row): ", probe_.last_error);
            }
        }
        const auto next = start + static_cast<int64_t>(config_.period_s * 1e9);
        while (!stop_.load() && service::steady_ns() < next) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
}

int HealthNode::failures_now(const ProbeState& s, int64_t now_ns) const {
    int failures = s.consecutive_failures;
    const double running_s = seconds(now_ns - s.cycle_start_ns);
    if (s.in_cycle && running_s > config_.deadline_s) {
        failures += 1 + static_cast<int>((running_s - config_.deadline_s) / config_.period_s);
    }
    return failures;
}

Status HealthNode::write_status(const std::map<std::string, StageAnswer>& stages, int64_t now_ns) {
    ProbeState p;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        p = probe_;
    }
    const int failures = failures_now(p, now_ns);
    std::string state = "ok";
    if (failures >= config_.failures) {
        state = "stuck";
    } else if (p.ok == 0) {
        state = "starting";
    }
    nlohmann::json j;
    j["pid"] = ::getpid();
    j["wall_time_s"] =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    j["uptime_s"] = seconds(now_ns - started_ns_);
    std::string last_error = p.last_error;
    if (p.in_cycle && seconds(now_ns - p.cycle_start_ns) > config_.deadline_s) {
        last_error = "a probe cycle has been blocked inside DDS/iceoryx for " +
                     std::to_string(seconds(now_ns - p.cycle_start_ns)) + " s";
    }
    j["roudi"] = {{"state", state},
                  {"consecutive_failures", failures},
                  {"failures_for_stuck", config_.failures},
                  {"cycles", p.cycles},
                  {"ok_cycles", p.ok},
                  {"last_rtt_ms", p.last_rtt_ms},
                  {"last_error", last_error},
                  // How long the probe cycle now under way has run (0: none under way).
                  {"cycle_running_s", p.in_cycle ? seconds(now_ns - p.cycle_start_ns) : 0.0},
                  {"period_s", config_.period_s},
                  {"deadline_s", config_.deadline_s}};
    nlohmann::json js = nlohmann::json::object();
    for (const auto& [name, a] : stages) {
        js[name] = {{"age_s", seconds(now_ns - a.last_ns)},
                    {"seq", a.seq},
                    {"epoch", a.epoch},
                    {"writer", a.writer},
                    {"writer_age_s", seconds(now_ns - a.writer_since_ns)},
                    {"epoch_age_s", seconds(now_ns - a.epoch_since_ns)},
                    {"answers", a.answers},
                    {"status", a.status}};
    }
    j["stages"] = js;
    const std::string tmp = config_.status_path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::trunc);
        out << j.dump(1) << "\n";
        if (!out) return Status(StatusCode::kInternal, "cannot write the status file " + tmp);
    }
    if (std::rename(tmp.c_str(), config_.status_path.c_str()) != 0) {
        return Status(StatusCode::kInternal, "cannot rename " + tmp + " to " + config_.status_path);
    }
    return Status::ok();
}

Status HealthNode::run() {
    started_ns_ = service::steady_ns();
    const std::string topic = dds::topic_name(config_.ns, dds::topics::kStageStatus);
    auto reader = dds::Reader<df_msg_StageStatus>::create(participant_, topic,
                                                          {dds::QosProfile::kStatus, 64});
    if (!reader) return reader.status();
    auto waitset = dds::WaitSet::create(participant_);
    if (!waitset) return waitset.status();
    DF_RETURN_IF_ERROR(waitset->attach_reader(reader->get()));
    log::info("probing RouDi every ", config_.period_s, " s (deadline ", config_.deadline_s,
              " s, stuck after ", config_.failures, " failures); stage answers from ", topic,
              "; status in ", config_.status_path);
    if (std::getenv("DF_LOG_LEVEL") == nullptr) log::set_level(log::Level::kWarn);  // 2 lines/cycle
    worker_ = std::thread([this] { probe_loop(); });
    std::map<std::string, StageAnswer> stages;
    int64_t next_write = 0;
    bool write_failed = false;
    while (!service::stop_requested()) {
        (void)waitset->wait(static_cast<dds_duration_t>(config_.write_period_s * 1e9 / 2));
        const int64_t now = service::steady_ns();
        auto taken = reader->take(
            [&](const df_msg_StageStatus& m, const dds_sample_info_t& info) {
                StageAnswer& a = stages[dds::get_name(m.stage)];
                if (a.writer != info.publication_handle) {
                    a.writer = info.publication_handle;
                    a.writer_since_ns = now;
                }
                if (a.epoch != m.header.epoch || a.answers == 0) {
                    a.epoch = m.header.epoch;
                    a.epoch_since_ns = now;
                }
                a.seq = m.header.seq;
                ++a.answers;
                a.last_ns = now;
                a.status = static_cast<int>(m.header.status);
            },
            64);
        if (!taken) log::warn("taking ", topic, ": ", taken.status().message());
        if (now >= next_write) {
            next_write = now + static_cast<int64_t>(config_.write_period_s * 1e9);
            const Status s = write_status(stages, now);
            if (!s && !write_failed) log::error(s.message());
            write_failed = !s;
        }
    }
    stop_.store(true);
    bool stuck;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stuck = probe_.in_cycle &&
                seconds(service::steady_ns() - probe_.cycle_start_ns) > config_.deadline_s;
    }
    if (stuck) {
        // Deleting DDS entities under a worker blocked inside iceoryx aborts the process.
        log::warn("stop requested; the probe is blocked inside iceoryx: exiting without cleanup");
        std::_Exit(0);
    }
    log::warn("stop requested");
    worker_.join();
    return Status::ok();
}

}  // namespace df::health
