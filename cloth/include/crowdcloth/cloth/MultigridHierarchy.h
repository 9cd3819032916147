#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"
#include "crowdcloth/core/SparseInterpolation.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// How the levels that no handed-in prolongation covers are built from the matrix alone. Both
/// read the coupling strength |A_ij|_F of the first matrix the hierarchy is built for and keep
/// the resulting prolongations for every later matrix of the same pattern.
enum class CoarseningKind : uint8_t {
    /// Greedy maximal independent set of the strong-coupling graph in vertex order (the coarse
    /// vertices); every other vertex interpolates from its strong coarse neighbours, weighted by
    /// strength (direct interpolation, as in classical AMG: Stueben 2001, "A review of algebraic
    /// multigrid"). One pass is red-black coarsening on the 4-8 grids; a level takes two passes
    /// composed (about 1/8 of the vertices above it), since the red-black level alone would cost
    /// as much to smooth as its parent (twice the blocks per row on half the rows).
    IndependentSet,
    /// Smoothed aggregation (Vanek, Mandel & Brezina 1996; for cloth Tamstorf, Jones & McCormick
    /// 2015): aggregates of strong neighbourhoods, a piecewise-constant tentative prolongation
    /// (the three translations, the near null space cloth keeps in every direction), smoothed by
    /// one damped Jacobi step of the strong part of the scalar operator trace(A_ij) / 3.
    SmoothedAggregation,
};

/// Settings of the multigrid preconditioner (MultigridPcg).
struct MultigridSettings {
    /// Prolongations from level k+1 to level k, finest first: element k maps the vertices of level
    /// k+1 (sourceCount) to those of level k (rowCount), so element 0 has one row per matrix row
    /// and element k+1 has one row per source of element k. Typically the 4-8 hierarchy's
    /// level-to-level interpolation. Empty = all levels algebraic (see `coarsening`); levels below
    /// the last one given are algebraic too, until `coarsestVertices` is reached.
    std::vector<SparseInterpolation> prolongations;
    /// [-] a handed-in level that keeps more than 1 / minCoarsening of the vertices above it is
    /// composed with the next handed-in one (repeatedly); [1, 16], 1 = every level as given.
    /// Default 3: a 4-8 level only halves the mesh, and its Galerkin operator has more blocks per
    /// row, so single 4-8 levels cost more to smooth than they save; pairs (a quarter) measured
    /// 15-25% faster per step on the bench's grids (MultigridBench.cpp).
    double minCoarsening = 3.0;
    /// How levels below the handed-in prolongations are built. Default IndependentSet: on the
    /// bench's 4-8 grids it needs fewer iterations and less time than smoothed aggregation (6.7
    /// against 9.0 iterations, 66 against 77 ms per step at 129^2, one thread) and matches the
    /// handed-in 4-8 levels paired (7.0 iterations, 68 ms); MultigridBench.cpp measures them.
    CoarseningKind coarsening = CoarseningKind::IndependentSet;
    /// [-] coupling i-j is strong when |A_ij|_F >= threshold * sqrt(|A_ii|_F |A_jj|_F); [0, 1).
    /// 0.1 keeps the stretch and shear couplings of cloth and drops the bending ones.
    double strengthThreshold = 0.1;
    /// [-] block Gauss-Seidel sweeps before (forward) and after (backward) each coarse
    /// correction; [1, 8]. More sweeps cost more per iteration than they save in iterations.
    int smoothingSweeps = 1;
    /// [vertices] a level with at most this many vertices is the coarsest; [1, 512]. It is
    /// solved by dense Cholesky.
    uint32_t coarsestVertices = 64;
    /// [-] levels including the finest; [2, 32]. When it cuts the hierarchy short, the coarsest
    /// level is smoothed instead of solved.
    int maxLevels = 20;

    /// Names the first invalid field (as "MultigridSettings.<field>").
    Status validate() const;
};

/// Structure of one level of a multigrid hierarchy: its block pattern, Gauss-Seidel colouring,
/// the prolongation from the next coarser level and the slot maps of the Galerkin triple product
/// A_{k+1} = P^T A_k P, computed in two stages (T = A_k P, then P^T T) with every sum in a fixed
/// order, so the numeric products run row-parallel and bit-identically for any thread count.
struct MultigridLevel {
    uint32_t size = 0;                           ///< vertices (block rows)
    std::vector<uint32_t> rowStart{0}, columns;  ///< block-CSR pattern, columns ascending
    std::vector<uint32_t> diagonal;              ///< slot of each row's diagonal block
    std::vector<uint32_t> colourStart{0};        ///< colour c: colourVertices[colourStart[c]..]
    std::vector<uint32_t> colourVertices;        ///< vertices by colour, ascending within one
    /// The numeric blocks are stored in Gauss-Seidel order: the rows of colourVertices one after
    /// another (position q holds vertex colourVertices[q]), each with its columns ascending, so
    /// a sweep reads them sequentially (2x faster at 129^2 than visiting the rows of the
    /// vertex-ordered matrix colour by colour).
    std::vector<uint32_t> storageStart{0};  ///< per position, its first stored block
    std::vector<uint32_t> storageColumns;   ///< column (vertex) of each stored block
    std::vector<uint32_t> sourceSlot;       ///< the pattern slot each stored block holds
    std::vector<uint32_t> storageOf;        ///< position of each vertex
    std::vector<uint32_t> storageDiagonal;  ///< stored slot of each vertex's diagonal block

    // Below: empty on the coarsest level.
    /// Prolongation from the next level: row i = sum of weight * coarse[source] over its terms.
    std::vector<uint32_t> prolongStart{0}, prolongSource;
    std::vector<double> prolongWeight;
    /// Its transpose (one row per coarse vertex, fine indices ascending): the restriction.
    std::vector<uint32_t> restrictStart{0}, restrictSource;
    std::vector<double> restrictWeight;
    /// Pattern of T = A P (rows of this level, columns of the next).
    std::vector<uint32_t> productStart{0}, productColumns;
    /// Per row i, for each block k of row i and each prolongation term of row columns[k] (in that
    /// order): the T slot it adds to. Row i's entries start at productMapStart[i].
    std::vector<uint32_t> productMapStart{0}, productMap;
    /// Per coarse row c, for each restriction term (i, w) and each T slot of row i (in that
    /// order): the coarse level's stored slot it adds to. Row c's entries start at
    /// galerkinMapStart[c].
    std::vector<uint32_t> galerkinMapStart{0}, galerkinMap;
};

/// The symbolic part of the multigrid preconditioner, built once per matrix pattern: levels,
/// prolongations (handed in or algebraic), coarse patterns and Galerkin slot maps. Immutable
/// after build(), so one hierarchy may serve several solvers of the same pattern.
class MultigridHierarchy {
public:
    /// Builds the hierarchy for `fine`'s pattern; an algebraic level reads `fine`'s values (and
    /// their Galerkin products) to judge coupling strength. Fails with InvalidArgument naming the
    /// bad prolongation, or when the settings are invalid.
    static Result<MultigridHierarchy> build(const BlockSparseMatrix& fine,
                                            const MultigridSettings& settings);
    /// Checks that `prolongations` chain from a level of `fineSize` vertices (see
    /// MultigridSettings::prolongations): sizes, source indices, finite weights.
    static Status checkProlongations(uint32_t fineSize,
                                     const std::vector<SparseInterpolation>& prolongations);

    /// True when `matrix` has the pattern this hierarchy was built for.
    bool matches(const BlockSparseMatrix& matrix) const;
    int levelCount() const { return static_cast<int>(mLevels.size()); }
    const MultigridLevel& level(int k) const { return mLevels[k]; }
    /// Blocks over all levels divided by the finest level's blocks.
    double operatorComplexity() const;
    /// True when the coarsest level is small enough for the dense direct solve.
    bool directCoarsest() const { return mDirectCoarsest; }

private:
    std::vector<MultigridLevel> mLevels;
    bool mDirectCoarsest = true;
};

} // namespace cc::cloth
