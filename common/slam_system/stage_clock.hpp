#pragma once
/// Wall-clock milliseconds for StageTimes (SlamSystem's steps).
#include <chrono>

namespace df::slam {

/// Milliseconds from `start` to now (steady clock).
inline double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

}  // namespace df::slam
