#pragma once

// Algebraic prolongations for the multigrid hierarchy, built from one matrix's values when no
// geometric interpolation is handed in (MultigridHierarchy.cpp). Internal to cloth/.

#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/SparseInterpolation.h"

namespace cc::cloth::detail {

/// One level's block pattern with values (Mat3 per slot), as the coarsening reads it.
struct LevelMatrix {
    const std::vector<uint32_t>& rowStart;
    const std::vector<uint32_t>& columns;
    const std::vector<uint32_t>& diagonal;
    const std::vector<Mat3>& values;
    uint32_t size() const { return static_cast<uint32_t>(rowStart.size() - 1); }
};

/// The strong couplings of a level, symmetric, without the diagonal: j is a strong neighbour of i
/// when |A_ij|_F >= threshold * sqrt(|A_ii|_F |A_jj|_F) (the measure of Vanek et al. 1996, which
/// is symmetric for a symmetric matrix). Neighbours ascend within a row.
struct StrengthGraph {
    std::vector<uint32_t> start{0};
    std::vector<uint32_t> neighbours;
    std::vector<double> strength;  // |A_ij|_F of each strong coupling
};

StrengthGraph strongCouplings(const LevelMatrix& a, double threshold);

/// Greedy maximal independent set in vertex order, direct interpolation weighted by strength.
SparseInterpolation independentSetProlongation(const StrengthGraph& graph);

/// The product P1 P2 (rows of p1, sources of p2): interpolation through an intermediate level.
SparseInterpolation compose(const SparseInterpolation& p1, const SparseInterpolation& p2);

/// Smoothed aggregation with a piecewise-constant tentative prolongation, smoothed by one damped
/// Jacobi step of the strong part of trace(A_ij) / 3.
SparseInterpolation smoothedAggregationProlongation(const LevelMatrix& a,
                                                    const StrengthGraph& graph);

} // namespace cc::cloth::detail
