#pragma once
// The step a garment update takes for the time since its last update.

#include <cmath>

namespace cc::detail {

constexpr double kStepGrid = 64.0;  ///< update steps per octave off whole frames (1.1 % apart)

/// n whole frames of frameDt when that is what elapsed (a host at a fixed rate), else the nearest
/// of 2^(k / kStepGrid) s. Elapsed times are sums of frame times that differ in their last bits
/// (and by the host's frame jitter); without snapping, garments would need factors of their own,
/// built mid-frame, and the factor cache would grow with every frame. The caller carries
/// elapsed - step to the next update, so no time is lost.
inline double updateStep(double elapsed, double frameDt) {
    const double frames = std::round(elapsed / frameDt);
    if (frames >= 1.0 && std::abs(elapsed - frames * frameDt) <= 1e-7 * elapsed) return frames * frameDt;
    return std::exp2(std::round(std::log2(elapsed) * kStepGrid) / kStepGrid);
}

} // namespace cc::detail
