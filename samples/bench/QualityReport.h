#pragma once

#include <cstdio>

namespace cc::bench {

constexpr int kQualitySteps = 180;    ///< 3 s of simulated time from rest
constexpr int kBarResolution = 65;    ///< vertices per side where the issue's bar is checked
constexpr double kBarSpeedup = 10.0;  ///< required ours / Bullet vertex-steps per second

/// Simulates the scene for kQualitySteps with Bullet and with our setups, prints a table of max
/// edge strain, sag, mean step time and speed relative to Bullet, then whether our implicit steps
/// reach kBarSpeedup x Bullet's speed at equal or lower strain. `full` runs all six setups plus
/// single-threaded PCG at 33^2 and 65^2 (about 4 minutes on 2 cores); otherwise only the two PCG
/// setups at 65^2 (the bar's fast path, about 25 s). Returns false if any simulation failed.
bool runQualityReport(std::FILE* out, bool full);

} // namespace cc::bench
