#pragma once
// Planar shadows: the matrix that flattens geometry onto the ground plane y = 0 along a
// directional light, exact for a flat ground.

#include "crowdcloth/render/Rgb.h"

namespace cc::render {

/// Column-major model matrix taking p to p - (p.y / l.y) l; `towardsLight` needs l.y > 0.
void groundShadowMatrix(const Rgb& towardsLight, float out[16]);

} // namespace cc::render
