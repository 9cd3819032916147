#pragma once

#include <chrono>

namespace cc::detail {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time since `start` (the frame's and each garment's measured costs).
inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace cc::detail
