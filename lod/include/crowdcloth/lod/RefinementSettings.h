#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::lod {

using Mat4 = Eigen::Matrix4d;

/// When a region of a garment refines or coarsens. Each criterion gives a triangle a demand
/// (measure / threshold); the triangle refines when any demand exceeds 1 and counts as quiet when
/// every demand is below `coarsenFraction`. A diamond merges after all its triangles have been quiet
/// for `quietFrames` consecutive adapt() calls (hysteresis against flicker).
struct RefinementSettings {
    double maxEdgePixels = 0.0;     ///< [px] refine while a triangle's longest edge projects longer;
                                    ///< needs AdaptInput::viewProjection; (0, 1e4]; 0 = off
    double maxDihedralAngle = 0.35; ///< [rad] refine where a triangle's normal turns more than this
                                    ///< from a neighbour's (curvature, wrinkles); [0, pi]; 0 = off
    double maxStrain = 0.0;         ///< [-] refine where |edge length / rest - 1| exceeds this; [0, 10]; 0 = off
    double maxKineticEnergy = 0.0;  ///< [J/kg] refine where the corners' mean 1/2 |v|^2 exceeds this (a
                                    ///< proxy for distance from equilibrium); [0, 1e6]; 0 = off
    double proximityDistance = 0.0; ///< [m] refine where a corner is closer to the body than this
                                    ///< (AdaptInput::bodyDistance); [0, 10]; 0 = off
    double coarsenFraction = 0.5;   ///< [-] a triangle is quiet when every demand is below this; (0, 1)
    uint32_t quietFrames = 10;      ///< [frames] quiet adapt() calls before a merge; [0, 100000]; 0 = at once
    uint32_t minLevel = 0;          ///< [-] never coarsen below this level; <= HierarchySettings::maxLevel
    uint32_t maxLevel = 0;          ///< [-] never refine above this level; 0 = HierarchySettings::maxLevel
    uint32_t vertexBudget = 0;      ///< [vertices] most active vertices; refinement stops there and the
                                    ///< least needed diamonds merge when over; 0 = HierarchySettings'
    uint32_t maxOperationsPerFrame = 0;  ///< [-] cap on refine + coarsen operations per adapt(); 0 = no cap

    /// Names the first field outside its range.
    Status validate() const;
};

/// What the criteria look at besides the garment's own state.
struct AdaptInput {
    const Mat4* viewProjection = nullptr;  ///< world -> clip space (OpenGL convention); null = no view
    double viewportWidth = 0.0;            ///< [px] > 0 when viewProjection is set
    double viewportHeight = 0.0;           ///< [px] > 0 when viewProjection is set
    /// [m] distance of each active simulation vertex (ActiveMesh index) from the body, or empty.
    /// A flag works too: pass 0 for "near" and a large value for "far".
    Span<const double> bodyDistance;
};

/// What one adapt() call did.
struct AdaptStats {
    uint32_t refined = 0;        ///< diamonds split (forced splits included)
    uint32_t coarsened = 0;      ///< diamonds merged
    uint32_t activeVertices = 0; ///< after the call
    bool changed() const { return refined + coarsened > 0; }
};

} // namespace cc::lod
