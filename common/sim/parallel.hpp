#pragma once
/// Row-parallel loops. Every row is computed by one call that depends only on its inputs, so the
/// result does not depend on how rows are shared out between threads.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace df::sim {

/// Number of threads to use for `requested` (<= 0: all hardware threads).
inline int thread_count(int requested) {
    if (requested > 0) return requested;
    return std::max(1u, std::thread::hardware_concurrency());
}

/// Calls fn(y_begin, y_end) over [0, rows) in chunks, on `threads` threads.
template <typename Fn>
void parallel_rows(int rows, int threads, Fn&& fn, int chunk = 4) {
    threads = std::min(thread_count(threads), std::max(1, rows / chunk));
    if (threads <= 1) {
        fn(0, rows);
        return;
    }
    std::atomic<int> next{0};
    auto worker = [&] {
        for (;;) {
            const int y0 = next.fetch_add(chunk);
            if (y0 >= rows) return;
            fn(y0, std::min(rows, y0 + chunk));
        }
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
}

}  // namespace df::sim
