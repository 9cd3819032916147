#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/cloth/ClothLevel.h"
#include "crowdcloth/cloth/ClothMaterial.h"
#include "crowdcloth/core/SparseInterpolation.h"
#include "crowdcloth/lod/ActiveMesh.h"
#include "crowdcloth/lod/CrowdScheduler.h"
#include "crowdcloth/lod/GarmentHierarchy.h"

namespace cc::detail {

/// A simulation vertex that follows the body: `slot` indexes CookedAsset::attachedVertices.
struct AttachedVertex {
    uint32_t sim = 0;
    uint32_t slot = 0;
};

/// One uniform level of a cooked garment: what every instance simulating that level shares.
struct CookedLevel {
    lod::GarmentHierarchy hierarchy;  ///< at this uniform level (for self-collision and tools)
    lod::ActiveMesh active;           ///< the solver's mesh (asset-space positions) and index maps
    std::shared_ptr<const cloth::ClothLevel> cloth;  ///< the solver's cooked data
    std::vector<uint32_t> attachedSlot;  ///< per attached node of `cloth`: its attachment slot
    SparseInterpolation render;       ///< render vertices from this level's simulation vertices
    std::vector<AttachedVertex> attached;  ///< by simulation index (welded copies included)
    double errorMetres = 0.0;         ///< [m] predicted drape error against the render level
    /// State transfer to the next finer level (simulation vertices of level + 1 from this one's):
    /// a new midpoint takes the mean position and velocity of its edge's ends, so momentum is kept
    /// (lod's split rule). Empty for the finest level.
    SparseInterpolation refine;
    /// State transfer to the next coarser level (from this one's vertices): positions stay, a
    /// merged midpoint hands half its mass and momentum to each end (lod's merge rule), so the
    /// velocities are mass-weighted means. Empty for level 0.
    SparseInterpolation coarsenPositions, coarsenVelocities;
};

/// A garment design cooked once and shared, immutable, by every instance (STYLE.md §5): the
/// pattern's 4-8 hierarchy at each uniform level, render topology and the attachment line.
struct CookedAsset {
    ClothAssetDesc desc;
    cloth::ClothMaterial material;
    std::vector<CookedLevel> levels;                       ///< coarsest first
    std::vector<std::array<uint32_t, 3>> renderTriangles;  ///< fixed for the asset's lifetime
    uint32_t renderVertexCount = 0;
    std::vector<uint32_t> attachedVertices;                ///< hierarchy ids of the attachment line
    Vec3 centroid = Vec3::Zero();                          ///< [m] asset space, of the render mesh
    double radius = 0.0;                                   ///< [m] bounding sphere about the centroid
};

/// Validates `desc`, builds the pattern, the hierarchy and every level. Fails naming the field.
Result<CookedAsset> cookClothAsset(const ClothAssetDesc& desc);

/// Digest of every field of a design (WorldSnapshot.cpp): snapshots and error tables check by it.
uint64_t designFingerprint(const ClothAssetDesc& design);

/// A base grid point of a pattern panel: (i, j) with i along u, j along v.
struct PatternPoint {
    uint32_t panel = 0, i = 0, j = 0;
};

/// Cooks a pattern built elsewhere (a garment fitted to a body, GarmentFit) like cookClothAsset,
/// hung from the given base grid points. `desc` supplies the material and levels; its sizes are
/// not used.
Result<CookedAsset> cookClothPattern(const ClothAssetDesc& desc, const lod::GarmentPattern& pattern,
                                     Span<const PatternPoint> attached);

} // namespace cc::detail
