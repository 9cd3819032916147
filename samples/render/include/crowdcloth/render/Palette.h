#pragma once
// Colours for the samples' --color-by overlays: a distinct colour per LOD level or solver, and a
// perceptual heat ramp for continuous values such as predicted error.

#include "crowdcloth/render/Rgb.h"

namespace cc::render {

/// A distinct colour per LOD level: 0 (finest) is warm, coarser levels step through the ramp to cool.
/// Levels beyond the palette repeat its last colour; negative levels are grey.
Rgb levelColour(int level);
/// A distinct, colour-blind friendly colour per solver index (Okabe-Ito); repeats after 8.
Rgb solverColour(int solver);
/// Turbo-like perceptual ramp: 0 dark blue, 0.5 yellow-green, 1 dark red; t is clamped to [0, 1].
Rgb heatColour(double t);

} // namespace cc::render
