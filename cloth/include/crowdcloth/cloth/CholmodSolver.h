#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// Direct solve of the same filtered system as solveFilteredPcg, through CHOLMOD's Cholesky
/// factorisation (via Eigen's CholmodSupport). Solves (S A S + (I - S)) y = S (b - A z) and returns
/// dv = z + S y; the added (I - S) keeps the matrix positive definite without changing y.
///
/// The scalar CSC pattern is built from the block pattern once, with every 3x3 block stored in
/// full, so filters and contacts never change it: CHOLMOD's symbolic analysis (fill-reducing
/// ordering) runs once per pattern and only the numeric factorisation runs per step.
class CholmodSolver {
public:
    CholmodSolver();
    ~CholmodSolver();
    CholmodSolver(CholmodSolver&&) noexcept;
    CholmodSolver& operator=(CholmodSolver&&) noexcept;

    Status solve(const BlockSparseMatrix& a, const std::vector<VertexFilter>& filters, const std::vector<Vec3>& b,
                 const std::vector<Vec3>& z, std::vector<Vec3>& outDv);
    /// How many symbolic analyses have run (1 while the pattern is unchanged).
    int analysisCount() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace cc::cloth
