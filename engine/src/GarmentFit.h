#pragma once

#include <vector>

#include "BodyAsset.h"
#include "CookedAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/lod/GarmentPattern.h"

namespace cc::detail {

/// Where every point of a panel starts: rings of world points (rows from the top side, v = height,
/// down to the hem), each sampled at equal arc length from u = 0 to u = width.
struct PanelPlacement {
    std::vector<std::vector<Vec3>> rings;

    /// World position of grid point (s, t) of the panel (s along u, t along v, both in [0, 1]).
    Vec3 at(double s, double t) const;
};

/// A garment design fitted to one body: the pattern (flared panels, 4-8 base grids), how it starts
/// around the body in its rest pose, the base grid points bound to the torso skin, and the sizes
/// it was cut to.
struct FittedGarment {
    ClothAssetDesc desc;                    ///< the design with width, length and hemWidth filled in
    lod::GarmentPattern pattern;
    std::vector<PanelPlacement> placement;  ///< per panel
    std::vector<PatternPoint> attached;
};

/// Fits a design to a body (see ClothAssetDesc for what is fitted and how sizes are checked).
/// Errors name the garment, the body and the problem (no torso, too small, too short).
Result<FittedGarment> fitGarment(const ClothAssetDesc& design, const BodyAsset& body);

/// Fits and cooks: every level starts in the fitted placement.
Result<CookedAsset> cookFittedGarment(const ClothAssetDesc& design, const BodyAsset& body);

} // namespace cc::detail
