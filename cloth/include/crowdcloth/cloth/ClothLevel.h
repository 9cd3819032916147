#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothMaterial.h"
#include "crowdcloth/cloth/MassSpringModel.h"
#include "crowdcloth/cloth/StrainLimiter.h"
#include "crowdcloth/core/ClothMesh.h"
#include "crowdcloth/core/Span.h"

namespace cc::cloth {

class SubstepFactor;

/// A spring between two nodes of a level (see ClothLevel for nodes).
struct LevelSpring {
    uint32_t a = 0, b = 0;    ///< nodes; in ClothLevel::attachedSprings(), b is the attached one
    double stiffness = 0.0;   ///< [N/m]
    double restLength = 0.0;  ///< [m]
};

/// A free node's long-range tether (Kim, Chentanez & Mueller 2012, "Long range attachments"): it
/// may not get farther from `anchor` (an attached node) than (1 + strain limit) x restLength.
struct LevelTether {
    uint32_t anchor = 0;
    double restLength = 0.0;  ///< [m] pattern-space distance to the anchor
};

/// What a level is cooked from: Provot springs over simulation vertices, the vertices driven by the
/// body, and the copies of one material point that a seam or a tube's wrap makes (lod's welds).
struct ClothLevelDesc {
    uint32_t vertexCount = 0;
    Span<const Spring> springs;                     ///< over simulation vertices
    Span<const double> masses;                      ///< [kg] per simulation vertex, > 0
    Span<const uint32_t> attachedVertices;          ///< follow targets every step (pins, attachments)
    Span<const std::array<uint32_t, 2>> welds;      ///< pairs of copies of one material point
    Span<const LimitedEdge> limitedEdges;           ///< edges Provot's strain limit watches
    Span<const Vec2> restPositions;                 ///< [m] pattern coordinates, for the tethers;
                                                    ///< empty = no tethers
};

/// One resolution of one garment, cooked once and shared read-only by every instance that
/// simulates it (Jolt's SoftBodySharedSettings, NvCloth's Fabric): the solver's numbering, masses,
/// springs, strain-limited edges, tethers, and the pattern of the local/global system matrix with
/// its fill-reducing ordering. Factors for a substep size are built from it on demand
/// (buildFactor) and shared the same way.
///
/// **Nodes.** Welded copies of one material point become one node, so forces cross seams inside
/// the solve instead of being glued by averaging afterwards. Free nodes come first, numbered in the
/// factor's fill-reducing order (CHOLMOD's AMD or METIS, whichever fills less), so the factor needs
/// no permutation at solve time; attached nodes follow, in ascending vertex order.
///
/// Thread-safety: immutable after cook(); any number of threads may read it at once.
class ClothLevel {
public:
    static Result<std::shared_ptr<const ClothLevel>> cook(const ClothLevelDesc& desc);
    /// Provot springs of `mesh` with `material`; every edge strain-limited, tethers from the rest shape.
    static Result<std::shared_ptr<const ClothLevel>> cookMesh(const ClothMesh& mesh, const ClothMaterial& material,
                                                              Span<const uint32_t> attachedVertices,
                                                              Span<const std::array<uint32_t, 2>> welds = {});

    uint32_t vertexCount() const { return uint32_t(mNodeOfVertex.size()); }
    uint32_t nodeCount() const { return uint32_t(mVertexOfNode.size()); }
    /// Nodes [0, freeNodeCount()) move with the forces; the rest follow their targets.
    uint32_t freeNodeCount() const { return mFreeNodeCount; }
    uint32_t attachedNodeCount() const { return nodeCount() - mFreeNodeCount; }
    const std::vector<uint32_t>& nodeOfVertex() const { return mNodeOfVertex; }
    /// The lowest simulation vertex of each node.
    const std::vector<uint32_t>& vertexOfNode() const { return mVertexOfNode; }
    const std::vector<double>& nodeMasses() const { return mNodeMass; }  ///< [kg]
    double totalMass() const { return mTotalMass; }                      ///< [kg] of the free nodes
    /// Stretch and shear springs between two free nodes, sorted by (a, b).
    const std::vector<LevelSpring>& freeSprings() const { return mFreeSprings; }
    /// Stretch and shear springs from a free node (a) to an attached one (b).
    const std::vector<LevelSpring>& attachedSprings() const { return mAttachedSprings; }
    /// Bending springs, the same two ways: orders of magnitude softer, so a factor leaves them
    /// out unless the substep makes them stiff (SubstepFactor::includesBending).
    const std::vector<LevelSpring>& freeBendSprings() const { return mFreeBendSprings; }
    const std::vector<LevelSpring>& attachedBendSprings() const { return mAttachedBendSprings; }
    /// Strain-limited edges over nodes (at least one end free), sorted.
    const std::vector<LimitedEdge>& limitedEdges() const { return mLimitedEdges; }
    /// Per free node; empty when nothing is attached or no rest shape was given.
    const std::vector<LevelTether>& tethers() const { return mTethers; }

    /// The local/global matrix for substeps of h [s], (0, 1]: M / h^2 + sum_s k_s (e_a - e_b)(e_a - e_b)^T
    /// over the free nodes (Liu et al. 2013, Bouaziz et al. 2014), factored as L L^T; bending
    /// springs join the sum only where they are stiff at this h (h^2 sum k / m > 0.5 at some
    /// node: explicit bending would be near its stability limit), with an ordering of their own. Costs a numeric factorisation (about 10 ms at 4,000
    /// nodes): build once per substep size and share.
    Result<std::shared_ptr<const SubstepFactor>> buildFactor(double h) const;

private:
    ClothLevel() = default;

    std::vector<uint32_t> mNodeOfVertex, mVertexOfNode;
    uint32_t mFreeNodeCount = 0;
    std::vector<double> mNodeMass;
    double mTotalMass = 0.0;
    std::vector<LevelSpring> mFreeSprings, mAttachedSprings, mFreeBendSprings, mAttachedBendSprings;
    std::vector<LimitedEdge> mLimitedEdges;
    std::vector<LevelTether> mTethers;
};

/// The Cholesky factor L of one level's local/global matrix for one substep size, stored
/// column-compressed for the solver's own triangular solves (many right-hand sides at once:
/// x, y and z of every instance in a batch). Immutable; shared by every instance of the level.
class SubstepFactor {
public:
    double substep() const { return mSubstep; }  ///< [s] h
    /// Whether the bending springs are in the matrix (else the solvers treat them explicitly).
    bool includesBending() const { return mIncludesBending; }
    uint32_t size() const { return uint32_t(mInverseDiagonal.size()); }
    std::size_t nonZeros() const { return mRows.size() + mInverseDiagonal.size(); }

    /// Solves (L L^T) X = B in place for interleaved right-hand sides: entry (row r, column c) at
    /// x[r * stride + c]. The stride is one of 4, 8, 12, 24 (x, y and z of a batch of 1, 2, 4 or 8
    /// instances, padded to whole SIMD pairs; padding entries must be finite). Columns do not
    /// interact and every column sees the same operations, so a column's result does not depend on
    /// what else is solved with it. `scratch` holds a permuted copy when the factor has its own
    /// ordering (bending included); it keeps its size between calls.
    void solveInPlace(double* x, int stride, std::vector<double>& scratch) const;

private:
    friend class ClothLevel;
    template <int R>
    void solve(double* x) const;

    double mSubstep = 0.0;
    bool mIncludesBending = false;
    std::vector<uint32_t> mColumnStart, mRows;     // strictly lower part by columns
    std::vector<double> mValues;
    std::vector<uint32_t> mRowStart, mRowColumns;  // the same by rows
    std::vector<double> mRowValues, mInverseDiagonal;
    std::vector<int> mPermutation;  // position -> node, when the factor has its own ordering
};

} // namespace cc::cloth
