#pragma once

#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"
#include "crowdcloth/cloth/ConstraintSet.h"

namespace cc::cloth {

struct PcgSettings {
    double relativeTolerance = 1e-3;  ///< [-] stop when |r| <= tol * |S (b - A z)|; (0, 1)
    int maxIterations = 2000;         ///< [-] cap; reaching it reports converged = false; >= 1
};

struct PcgResult {
    int iterations = 0;
    double relativeResidual = 0.0;
    bool converged = true;
};

/// Scratch of the solver, kept between steps so the hot path does not allocate. The iteration
/// runs on 4-padded copies (3x3 blocks as 4x3 columns, vectors as 4-vectors with w = 0): the
/// kernel is compute-bound, and padding lets every block product vectorise (2.6x faster than
/// unaligned 3x3 products on the development machine).
struct PcgWorkspace {
    using Vec4 = Eigen::Vector4d;
    using Block = Eigen::Matrix<double, 4, 3>;
    std::vector<Block> blocks, inverseDiagonal;
    std::vector<Vec4> solution, residual, direction, product, preconditioned;
    std::vector<Vec4> filterNormal;   // plane normal, or zero
    std::vector<double> filterScale;  // 0 for a Target vertex, else 1
    std::vector<double> partials;
};

/// Modified PCG of Baraff & Witkin (1998), in the constrained-subspace form of Ascher & Boxerman
/// (2003): solves (S A S) y = S (b - A z) and returns dv = z + S y, so constrained directions take
/// exactly z while the free ones solve the system. Block-Jacobi preconditioned (the inverse of each
/// 3x3 diagonal block). `inOutDv` is the warm start on input (its free part is kept; pass z or zero
/// for a cold start) and the solution on output.
///
/// Three fused passes per iteration (product, update, direction), each a row-parallel loop over
/// fixed vertex chunks; dot products add chunk partials in index order, so the iterate sequence
/// is bit-identical for any thread count.
PcgResult solveFilteredPcg(const BlockSparseMatrix& a, const std::vector<VertexFilter>& filters,
                           const std::vector<Vec3>& b, const std::vector<Vec3>& z, std::vector<Vec3>& inOutDv,
                           const PcgSettings& settings, const ParallelSettings& parallel, PcgWorkspace& work);

/// Bytes one PCG iteration streams per vertex for a matrix of `blocksPerRow` 3x3 blocks per row
/// (the figure the benchmarks compare against measured memory bandwidth).
double pcgBytesPerVertexIteration(double blocksPerRow);

} // namespace cc::cloth
