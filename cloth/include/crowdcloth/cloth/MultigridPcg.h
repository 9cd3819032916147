#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/cloth/FilteredPcg.h"
#include "crowdcloth/cloth/MultigridHierarchy.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// The filtered system of solveFilteredPcg, (S A S) y = S (b - A z), dv = z + S y, solved by CG
/// preconditioned with a symmetric multigrid V-cycle (Tamstorf, Jones & McCormick 2015, "Smoothed
/// aggregation multigrid for cloth simulation"), so the iteration count stays nearly constant
/// as the mesh is refined where block Jacobi's grows with the resolution.
///
/// Prefiltering (Tamstorf et al. section 5): the V-cycle works on the filtered operator
/// S A S + (I - S), and every level's prolongation is filtered on both sides, P' = S_k P S_k+1,
/// so no coarse correction moves a pinned vertex or pushes a contact into its plane. A coarse
/// vertex's filter S_k+1 drops the directions that all of its fine support has lost (e.g. the
/// normal of a patch of contacts with one plane); everywhere else it is the identity. Coarse
/// operators are Galerkin products A_k+1 = P'^T A_k P', recomputed from each step's matrix
/// through slot maps fixed per pattern.
///
/// The V-cycle: `smoothingSweeps` multicolour block Gauss-Seidel sweeps forward before the coarse
/// correction and as many backward after it (the adjoint), an exact dense Cholesky solve on the
/// coarsest level. So the preconditioner is symmetric positive definite, as CG needs.
///
/// Deterministic for any thread count: Gauss-Seidel updates one colour at a time (vertices of a
/// colour share no block), Galerkin sums and restrictions are taken per row in a fixed order, and
/// dot products add fixed chunks in index order. The hierarchy is built on the first solve (and
/// again only if the pattern changes); after that a solve allocates nothing. Not thread-safe; one
/// instance per garment.
///
///   MultigridPcg mg(settings.multigrid);
///   PcgResult result;
///   if (Status s = mg.solve(a, filters, b, z, dv, pcgSettings, parallel, result); !s) return s;
class MultigridPcg {
public:
    explicit MultigridPcg(MultigridSettings settings = {});
    ~MultigridPcg();
    MultigridPcg(MultigridPcg&&) noexcept;
    MultigridPcg& operator=(MultigridPcg&&) noexcept;

    /// Solves like solveFilteredPcg: `inOutDv` is the warm start (its free part is kept) and the
    /// solution. Fails with InvalidArgument when the sizes of filters, b, z and inOutDv differ
    /// from the matrix's, or the settings or prolongations are invalid; with NumericalFailure when
    /// the matrix is not positive definite or not finite. Not converging within
    /// settings.maxIterations is not an error: outResult.converged says so.
    Status solve(const BlockSparseMatrix& a, const std::vector<VertexFilter>& filters,
                 const std::vector<Vec3>& b, const std::vector<Vec3>& z, std::vector<Vec3>& inOutDv,
                 const PcgSettings& settings, const ParallelSettings& parallel,
                 PcgResult& outResult);

    /// Builds (if needed) the hierarchy and the coarse operators for `a` and `filters`, as solve()
    /// does first; then applyPreconditioner() may be called.
    Status setUp(const BlockSparseMatrix& a, const std::vector<VertexFilter>& filters,
                 const ParallelSettings& parallel);
    /// outZ = S V(S r), the preconditioner of the last setUp() or solve() (for tests).
    void applyPreconditioner(const std::vector<Vec3>& r, std::vector<Vec3>& outZ,
                             const ParallelSettings& parallel);

    /// The hierarchy of the last solve; null before the first.
    const MultigridHierarchy* hierarchy() const;
    /// How many times a hierarchy was built (1 while the pattern is unchanged).
    int hierarchyBuilds() const;
    const MultigridSettings& settings() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace cc::cloth
