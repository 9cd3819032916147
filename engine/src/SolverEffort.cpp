// How much solver work a World spends: the effort per level (WorldDesc::effortAt) and three
// choices of speed against accuracy a host picks from (WorldDesc::applyPreset). The presets' efforts
// are measured, not guessed: `cc_crowd --tradeoff` restarts every configuration in short windows
// from a converged reference and prints `BAR presets` (is each preset, at the level its tolerance
// gets at the study camera, on every scene's front? README, "Speed against accuracy").
#include <algorithm>
#include <cmath>
#include <string>

#include "crowdcloth/World.h"

namespace cc {
namespace {

struct PresetValues {
    double pixelTolerance;
    uint32_t substeps, solverIterations;
};

// Measured at the finest shipped level (cc_crowd --tradeoff, README), configurations interleaved
// window by window: the mesh, not the solver, sets most of the error there, and which effort is on
// the front follows the motion. 1 x 1 is the walking cape's (cheapest and nearest: more substeps
// make its edges catch the arms), 2 x 1 the skirt's, 4 x 4 the running cape's (the only scene
// where effort buys accuracy). No one effort is on all three fronts.
constexpr PresetValues kPresets[] = {
    {4.0, 1, 1},  // Fast
    {1.0, 2, 1},  // Balanced
    {0.5, 4, 4},  // Quality
};

} // namespace

WorldDesc::Effort WorldDesc::effortAt(uint32_t level, uint32_t levelCount, double frameDt) const {
    const int below = std::max(0, int(levelCount) - 1 - int(level));
    const int perEffortFrame = std::max(1, int(substeps) >> ((below + 1) / 2));
    // Rounded, so that frame times jittering about 1/60 s keep the substeps (and their factors).
    const double scaled = std::round(double(perEffortFrame) * frameDt / kEffortFrame);
    return {uint32_t(std::clamp(scaled, 1.0, 64.0)), // 64: the most substeps a desc may name
            uint32_t(std::max(1, int(solverIterations) - below))};
}

Status WorldDesc::applyPreset(QualityPreset preset) {
    const auto index = uint32_t(preset);
    if (index >= sizeof(kPresets) / sizeof(kPresets[0]))
        return Status::invalidArgument("QualityPreset " + std::to_string(index) +
                                       " is not a preset (0 Fast, 1 Balanced, 2 Quality)");
    pixelTolerance = kPresets[index].pixelTolerance;
    substeps = kPresets[index].substeps;
    solverIterations = kPresets[index].solverIterations;
    return Status::ok();
}

} // namespace cc
