#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/cloth/ClothState.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/cloth/StencilSet.h"

namespace cc::cloth {

/// An edge whose stretch is limited, with its rest length [m].
struct LimitedEdge {
    uint32_t a, b;
    double restLength;
};

/// Provot's strain limiting ("Deformation constraints in a mass-spring model to describe rigid
/// cloth behavior", 1995): after a step, edges stretched beyond (1 + limit) of their rest length
/// are shortened back by moving their ends toward each other (in inverse-mass proportion;
/// constrained vertices do not move), and velocities get the same correction divided by h.
/// Edges are processed colour by colour (Gauss-Seidel, deterministic for any thread count).
class StrainLimiter {
public:
    StrainLimiter() = default;
    StrainLimiter(uint32_t vertexCount, std::vector<LimitedEdge> edges);

    /// Runs up to `maxPasses` sweeps until no edge exceeds the limit by more than 1e-3 of it.
    /// Returns the number of sweeps run.
    int apply(double limit, int maxPasses, double h, const ConstraintSet& constraints, ClothState& state,
              const ParallelSettings& parallel) const;
    /// Largest (length / rest length - 1) over the edges.
    double maxStrain(const std::vector<Vec3>& positions) const;
    const std::vector<LimitedEdge>& edges() const { return mEdges; }

private:
    std::vector<LimitedEdge> mEdges;
    StencilSet<2> mStencils;
};

} // namespace cc::cloth
