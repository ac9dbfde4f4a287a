// tap echo / hz / bw / delay.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <iostream>

#include "commands.hpp"
#include "core/log.hpp"
#include "dds/cdr.hpp"
#include "dds/msg_convert.hpp"
#include "print.hpp"

namespace df::tap {
namespace {

Result<std::vector<Subscription>> subscribe_one(const dds::Participant& p, const std::string& topic,
                                                const CommonOptions& o) {
    auto sub = subscribe(p, topic, o.wait_s, o.depth);
    if (!sub) return sub.status();
    std::vector<Subscription> subs;
    subs.push_back(std::move(*sub));
    return subs;
}

struct Window {
    explicit Window(size_t n) : max(n) {}
    void add(double v) {
        values.push_back(v);
        if (values.size() > max) values.pop_front();
    }
    double mean() const {
        double s = 0;
        for (double v : values) s += v;
        return values.empty() ? 0 : s / static_cast<double>(values.size());
    }
    double percentile(double p) const {
        if (values.empty()) return 0;
        std::vector<double> v(values.begin(), values.end());
        std::sort(v.begin(), v.end());
        const size_t k = static_cast<size_t>(std::lround(p * static_cast<double>(v.size() - 1)));
        return v[k];
    }
    double stddev() const {
        const double m = mean();
        double s = 0;
        for (double v : values) s += (v - m) * (v - m);
        return values.size() > 1 ? std::sqrt(s / static_cast<double>(values.size() - 1)) : 0;
    }
    size_t max;
    std::deque<double> values;
};

int finish(const Status& s) {
    if (!s) {
        log::error(s.message());
        return 1;
    }
    return 0;
}

}  // namespace

int cmd_echo(const dds::Participant& p, const std::string& topic, const CommonOptions& o,
             int max_items) {
    auto subs = subscribe_one(p, topic, o);
    if (!subs) return finish(subs.status());
    const dds::TypeInfo* type = (*subs)[0].type;
    return finish(run_loop(
        p, *subs, o.limits,
        [&](size_t, const void* sample, const dds_sample_info_t&) {
            std::cout << print_sample(*type, sample, max_items) << "---\n" << std::flush;
        },
        nullptr));
}

int cmd_hz(const dds::Participant& p, const std::string& topic, const CommonOptions& o) {
    auto subs = subscribe_one(p, topic, o);
    if (!subs) return finish(subs.status());
    Window intervals(static_cast<size_t>(o.window));
    int64_t last = -1;
    auto report = [&] {
        if (intervals.values.empty()) {
            std::printf("no new messages\n");
        } else {
            const double m = intervals.mean();
            std::printf("average rate: %.3f\n\tmin: %.4fs max: %.4fs std dev: %.5fs window: %zu\n",
                        m > 0 ? 1.0 / m : 0.0, intervals.percentile(0), intervals.percentile(1),
                        intervals.stddev(), intervals.values.size() + 1);
        }
        std::fflush(stdout);
    };
    const Status s = run_loop(
        p, *subs, o.limits,
        [&](size_t, const void*, const dds_sample_info_t&) {
            const auto now = static_cast<int64_t>(dds::wall_ns());
            if (last >= 0) intervals.add((now - last) * 1e-9);
            last = now;
        },
        report);
    report();
    return finish(s);
}

int cmd_bw(const dds::Participant& p, const std::string& topic, const CommonOptions& o) {
    auto subs = subscribe_one(p, topic, o);
    if (!subs) return finish(subs.status());
    const dds::TypeInfo* type = (*subs)[0].type;
    std::deque<std::pair<int64_t, size_t>> window;  // (receive ns, bytes)
    auto report = [&] {
        if (window.size() < 2) {
            std::printf("no new messages\n");
        } else {
            size_t bytes = 0;
            for (auto& w : window) bytes += w.second;
            const double span = (window.back().first - window.front().first) * 1e-9;
            std::printf(
                "average: %.2f MB/s\n\tmean: %.2f KB min: %.2f KB max: %.2f KB window: %zu\n",
                span > 0 ? bytes / span / 1e6 : 0.0,
                bytes / 1e3 / static_cast<double>(window.size()),
                std::min_element(
                    window.begin(), window.end(),
                    [](auto& a, auto& b) {
                        return a.second < b.second;
                    })->second /
                    1e3,
                std::max_element(
                    window.begin(), window.end(),
                    [](auto& a, auto& b) {
                        return a.second < b.second;
                    })->second /
                    1e3,
                window.size());
        }
        std::fflush(stdout);
    };
    const Status s = run_loop(
        p, *subs, o.limits,
        [&](size_t, const void* sample, const dds_sample_info_t&) {
            const size_t bytes = type->fixed_size() ? type->descriptor->m_size
                                                    : dds::to_cdr(type->descriptor, sample).size();
            window.emplace_back(static_cast<int64_t>(dds::wall_ns()), bytes);
            if (window.size() > static_cast<size_t>(o.window)) window.pop_front();
        },
        report);
    report();
    return finish(s);
}

int cmd_delay(const dds::Participant& p, const std::string& topic, const CommonOptions& o) {
    auto subs = subscribe_one(p, topic, o);
    if (!subs) return finish(subs.status());
    Window delays(static_cast<size_t>(o.window));
    auto report = [&] {
        if (delays.values.empty()) {
            std::printf("no new messages\n");
        } else {
            std::printf(
                "delay (receive - capture): mean %.3f ms p50 %.3f ms p99 %.3f ms min %.3f ms max "
                "%.3f ms window: %zu\n",
                delays.mean(), delays.percentile(0.5), delays.percentile(0.99),
                delays.percentile(0), delays.percentile(1), delays.values.size());
        }
        std::fflush(stdout);
    };
    const Status s = run_loop(
        p, *subs, o.limits,
        [&](size_t, const void* sample, const dds_sample_info_t&) {
            // Every type starts with df_msg_Header.
            const auto* h = static_cast<const df_msg_Header*>(sample);
            if (o.ok_only && h->status != df_msg_FRAME_OK) return;
            delays.add((static_cast<double>(dds::wall_ns()) - static_cast<double>(h->capture_ns)) *
                       1e-6);
        },
        report);
    report();
    return finish(s);
}

}  // namespace df::tap
