#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace cc::bench {

/// What the solver-front study runs.
struct SolverFrontOptions {
    std::vector<int> resolutions{17, 33, 65, 129};  ///< vertices per side
    /// Resolutions whose trajectory error is measured (the converged reference at 129^2 takes
    /// about 10 minutes the first time; references are cached in `cacheDirectory`).
    std::vector<int> referenceResolutions{17, 33, 65};
    std::string cacheDirectory = "cc_bench_cache";
};

/// The speed/accuracy front of every solver configuration on the bench sheet (BenchScenes.h, with
/// Provot springs and no Rayleigh damping, so every solver simulates the same model): per
/// resolution and configuration, ms per 1/60 s frame (one thread), iterations, max edge strain over
/// 3 s, RMS trajectory error against the converged small-step reference over the first 0.5 s, and
/// sag after 3 s; Bullet's default cloth beside it. Prints the table and the machine-readable
/// `BAR solver65 ...` line. Returns false if a simulation failed.
bool runSolverFront(std::FILE* out, const SolverFrontOptions& options);

} // namespace cc::bench
