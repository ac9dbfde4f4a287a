#pragma once
/// Internal to df_map: a task loop on a few threads. Tasks must write disjoint outputs, so that
/// the result does not depend on which thread runs which task.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace df::map::detail {

/// Threads to use for `requested` (<= 0: all hardware threads).
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// Calls task(i) for every i in [0, tasks) on up to `threads` threads (the caller's included).
template <typename Task>
void run_tasks(int tasks, int threads, const Task& task) {
    threads = std::min(threads, tasks);
    if (threads <= 1) {
        for (int i = 0; i < tasks; ++i) task(i);
        return;
    }
    std::atomic<int> next{0};
    const auto worker = [&] {
        for (int i = next.fetch_add(1); i < tasks; i = next.fetch_add(1)) task(i);
    };
    std::vector<std::thread> pool;
    pool.reserve(static_cast<size_t>(threads - 1));
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

}  // namespace df::map::detail
