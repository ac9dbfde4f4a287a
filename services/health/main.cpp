// df_health: RouDi health probe and per-stage answer ages for dfsup (services/health/
// health_node.hpp). dfsup starts it in every shared-memory pipeline and reads its JSON file.
#include <CLI/CLI.hpp>

#include "core/log.hpp"
#include "health_node.hpp"
#include "service/service.hpp"

int main(int argc, char** argv) {
    df::log::set_component("health");
    df::health::HealthConfig config;
    uint32_t domain_id = 0;
    CLI::App app{
        "df_health: checks every period that a sample crosses iceoryx shared memory through new "
        "ports (RouDi alive and serving) and records the age of each stage's last "
        "<ns>/stage_status; writes both as JSON for dfsup"};
    app.add_option("--status", config.status_path, "JSON status file (written atomically)")
        ->required();
    app.add_option("--ns", config.ns, "topic namespace")->capture_default_str();
    app.add_option("--domain", domain_id, "DDS domain id")->capture_default_str();
    app.add_option("--period-s", config.period_s, "seconds between probe cycles, (0.05, 60]")
        ->capture_default_str();
    app.add_option("--deadline-s", config.deadline_s,
                   "a probe cycle must see its sample back within this, (0.05, 60]")
        ->capture_default_str();
    app.add_option("--failures", config.failures,
                   "failed cycles in a row that make RouDi 'stuck', [1, 100]")
        ->capture_default_str();
    app.add_option("--write-period-s", config.write_period_s,
                   "status file rewritten this often, (0.01, 10]")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (auto s = df::health::validate(config); !s) {
        df::log::error(s.message());
        return 2;
    }
    df::service::install_stop_handlers();
    df::service::keep_frame_buffers();
    df::config::DdsConfig dds;
    dds.set_domain_id(domain_id);
    dds.set_transport("shm");  // the probe is about shared memory: no RouDi is an error
    dds.set_ns(config.ns);
    auto participant = df::service::make_participant(dds);
    if (!participant) {
        df::log::error(participant.status().message());
        return 1;
    }
    df::health::HealthNode node(config, *participant);
    if (auto s = node.run(); !s) {
        df::log::error(s.message());
        return 1;
    }
    return 0;
}
