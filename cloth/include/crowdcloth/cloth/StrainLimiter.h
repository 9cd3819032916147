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
///
/// Edge sweeps alone converge slowly far from the pins (a chain of L edges needs ~L^2 sweeps:
/// 50 sweeps left 37% strain on a 10 x 10 sheet hung by two corners). So each sweep starts with
/// long-range tethers (Kim, Chentanez & Mueller 2012): every free vertex stays within (1 + limit)
/// of its pattern-space distance to the nearest Target vertex, which removes the global stretch
/// in one pass and leaves the edges only local work.
class StrainLimiter {
public:
    StrainLimiter() = default;
    /// `restPositions` (pattern coordinates, one per vertex) enable the tethers; may be empty.
    StrainLimiter(uint32_t vertexCount, const std::vector<LimitedEdge>& edges, std::vector<Vec2> restPositions = {});

    /// Runs up to `maxPasses` sweeps until no edge exceeds the limit by more than 1e-3 of it.
    /// Returns the number of sweeps run.
    int apply(double limit, int maxPasses, double h, const ConstraintSet& constraints, ClothState& state,
              const ParallelSettings& parallel) const;
    /// Largest (length / rest length - 1) over the edges.
    double maxStrain(const std::vector<Vec3>& positions) const;

private:
    // Finds each free vertex's nearest Target vertex in pattern space (once per apply(): it depends
    // only on the rest shape and the pins). Returns false when there are no tethers.
    bool bindTethers(const ConstraintSet& constraints) const;
    // Pulls free vertices back inside their tether.
    bool applyTethers(double limit, double h, const ConstraintSet& constraints, ClothState& state,
                      const ParallelSettings& parallel) const;

    std::vector<LimitedEdge> mEdges;
    std::vector<Vec2> mRest;
    mutable std::vector<uint32_t> mTargets;     // scratch: the Target vertices of the current call
    mutable std::vector<uint32_t> mAnchor;      // scratch: nearest Target vertex per vertex
    mutable std::vector<double> mTetherLength;  // scratch: [m] its rest distance
    StencilSet<2> mStencils;
};

} // namespace cc::cloth
