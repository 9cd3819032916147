#pragma once

#include <vector>

#include "GarmentFit.h"
#include "crowdcloth/lod/GarmentPattern.h"

namespace cc::detail {

/// Shortens every stretched edge of a garment's placement grids to its rest length, each panel's
/// top row held where it is attached, sewn sides kept together. The fit builds each row to clear
/// the body and to have its rest length, but consecutive rows may lie further apart than the cloth
/// between them (a shoulder jutting out under a cape, folds opening below the hands of a circle
/// skirt, rows matched by arc length along rings of different shapes): measured up to 450 % strain
/// on the mannequin and 1,100 % on other humanoids. Stretched, the first step snaps the cloth back
/// at metres per second (a circle skirt flew up round the arms). Follow-the-leader from the top
/// (Mueller et al. 2012, "Fast simulation of inextensible hair and fur": a row moves only towards
/// the row above it, already placed), then the row's own edges, then the seams; edges shorter than
/// rest stay as they are (compression is the folds the grid cannot show).
void relaxPlacement(const lod::GarmentPattern& pattern, std::vector<PanelPlacement>& placement);

} // namespace cc::detail
