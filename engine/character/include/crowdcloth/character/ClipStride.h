#pragma once

#include "crowdcloth/character/BodyRegions.h"
#include "crowdcloth/character/Character.h"

namespace cc {

/// [rad] The widest stride in a character's clips: half the angle between its thighs (hip joint
/// to knee) seen from the side (in the plane of `regions.forward` and up), the largest over every
/// clip sampled at 30 Hz. A skirt or dress must clear both knees at it (GarmentFit's A-line cut).
/// The knee is the joint of each leg's main chain (the child with the most joints below it at
/// each step) nearest halfway down it: rigs put twist and helper joints between the hip and the
/// knee, and beside the shin. 0 when the body has no clips, no legs in its regions, or
/// no clip moves them.
double widestClipStride(const Character& character, const BodyRegions& regions);

} // namespace cc
