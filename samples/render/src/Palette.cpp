#include "crowdcloth/render/Palette.h"

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace cc::render {
namespace {

// Google's Turbo colormap sampled at t = 0, 1/8, ..., 1; interpolated linearly in between.
constexpr Rgb kTurbo[] = {
    {0.190f, 0.072f, 0.232f}, {0.276f, 0.421f, 0.891f}, {0.158f, 0.736f, 0.923f},
    {0.197f, 0.949f, 0.595f}, {0.644f, 0.990f, 0.234f}, {0.960f, 0.798f, 0.190f},
    {0.981f, 0.471f, 0.085f}, {0.796f, 0.178f, 0.025f}, {0.480f, 0.016f, 0.011f},
};

// Okabe-Ito: eight colours that stay distinct under the common colour-vision deficiencies.
constexpr Rgb kOkabeIto[] = {
    {0.902f, 0.624f, 0.000f}, {0.337f, 0.706f, 0.914f}, {0.000f, 0.620f, 0.451f}, {0.941f, 0.894f, 0.259f},
    {0.000f, 0.447f, 0.698f}, {0.835f, 0.369f, 0.000f}, {0.800f, 0.475f, 0.655f}, {0.600f, 0.600f, 0.600f},
};

// LOD levels 0..4 sampled from the hot end of the ramp towards the cold end, so "finest" reads as hot.
constexpr double kLevelHeat[] = {0.95, 0.72, 0.5, 0.3, 0.12};

} // namespace

Rgb heatColour(double t) {
    const double clamped = std::clamp(t, 0.0, 1.0);
    const double scaled = clamped * double(std::size(kTurbo) - 1);
    const std::size_t lower = std::min(std::size_t(scaled), std::size(kTurbo) - 2);
    const float f = float(scaled - double(lower));
    Rgb c{};
    for (int k = 0; k < 3; ++k) c[k] = kTurbo[lower][k] + f * (kTurbo[lower + 1][k] - kTurbo[lower][k]);
    return c;
}

Rgb levelColour(int level) {
    if (level < 0) return {0.5f, 0.5f, 0.5f};
    const std::size_t index = std::min(std::size_t(level), std::size(kLevelHeat) - 1);
    return heatColour(kLevelHeat[index]);
}

Rgb solverColour(int solver) {
    const int n = int(std::size(kOkabeIto));
    return kOkabeIto[((solver % n) + n) % n];
}

} // namespace cc::render
