#include "crowdcloth/cloth/FilteredPcg.h"

#include <cmath>

#include "PaddedBlocks.h"

namespace cc::cloth {
namespace {

using detail::Block;
using detail::chunkedPass;
using detail::padBlock;
using detail::padVector;
using detail::times;
using detail::Vec4;

struct Solver {
    const BlockSparseMatrix& a;
    PcgWorkspace& w;

    EIGEN_STRONG_INLINE Vec4 project(int64_t i, const Vec4& v) const {
        const Vec4& n = w.filterNormal[i];
        return w.filterScale[i] * (v - n * n.dot(v));
    }
    EIGEN_STRONG_INLINE Vec4 row(int64_t i, const std::vector<Vec4>& x) const {
        Vec4 sum = Vec4::Zero();
        for (uint32_t k = a.rowStart()[i]; k < a.rowStart()[i + 1]; ++k) sum += times(w.blocks[k], x[a.columns()[k]]);
        return sum;
    }
};

} // namespace

double pcgBytesPerVertexIteration(double blocksPerRow) {
    // Product pass: padded blocks (96 B) + column indices (4 B) per block, row start (4 B), the
    // direction gathered once (32 B; neighbours hit the cache), filter (40 B), product written (32 B).
    const double product = blocksPerRow * (96.0 + 4.0) + 4.0 + 32.0 + 40.0 + 32.0;
    // Update pass: read solution, residual, direction, product, inverse diagonal (96 B), filter;
    // write solution, residual, preconditioned residual.
    const double update = 4 * 32.0 + 96.0 + 40.0 + 3 * 32.0;
    // Direction pass: read preconditioned residual and direction, write direction.
    const double direction = 3 * 32.0;
    return product + update + direction;
}

PcgResult solveFilteredPcg(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f,
                           const std::vector<Vec3>& b, const std::vector<Vec3>& z, std::vector<Vec3>& dv,
                           const PcgSettings& settings, const ParallelSettings& parallel, PcgWorkspace& w) {
    const int64_t n = a.size();
    w.blocks.resize(a.blockCount());
    w.inverseDiagonal.resize(n);
    for (auto* v : {&w.solution, &w.residual, &w.direction, &w.product, &w.preconditioned, &w.filterNormal}) v->resize(n);
    w.filterScale.resize(n);
    auto& x = w.solution;
    auto& r = w.residual;
    auto& p = w.direction;
    auto& q = w.product;
    auto& s = w.preconditioned;
    const Solver solver{a, w};

    // Padded copies; the warm guess keeps its free part and takes z on the constrained one. The
    // fixed part z is solved exactly, so the right-hand side is S (b - A z) and the tolerance is
    // relative to its norm.
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            for (uint32_t k = a.rowStart()[i]; k < a.rowStart()[i + 1]; ++k) w.blocks[k] = padBlock(a.block(k));
            w.inverseDiagonal[i] = padBlock(a.block(a.diagonalSlot(uint32_t(i))).inverse());
            w.filterScale[i] = f[i].kind == ConstraintKind::Target ? 0.0 : 1.0;
            w.filterNormal[i] = f[i].kind == ConstraintKind::ContactPlane ? padVector(f[i].normal) : Vec4::Zero();
            p[i] = padVector(z[i]);  // z, padded, for the right-hand side below
            x[i] = padVector(z[i] + f[i].project(dv[i] - z[i]));
        }
    });
    const double rhsNorm2 = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
        return Eigen::Vector2d(solver.project(i, padVector(b[i]) - solver.row(i, p)).squaredNorm(), 0.0);
    })[0];
    PcgResult result;
    if (rhsNorm2 == 0.0) {
        dv = z;
        return result;
    }
    Eigen::Vector2d rs = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
        r[i] = solver.project(i, padVector(b[i]) - solver.row(i, x));
        s[i] = solver.project(i, times(w.inverseDiagonal[i], r[i]));
        return Eigen::Vector2d(r[i].dot(s[i]), r[i].squaredNorm());
    });
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) p[i] = s[i];
    });
    const double tol2 = settings.relativeTolerance * settings.relativeTolerance * rhsNorm2;
    double rho = rs[0];
    double r2 = rs[1];
    while (r2 > tol2 && result.iterations < settings.maxIterations) {
        const double pq = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
            q[i] = solver.project(i, solver.row(i, p));
            return Eigen::Vector2d(p[i].dot(q[i]), 0.0);
        })[0];
        if (!(pq > 0.0)) break;  // direction of zero curvature: nothing more to gain (or not SPD)
        const double alpha = rho / pq;
        rs = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            s[i] = solver.project(i, times(w.inverseDiagonal[i], r[i]));
            return Eigen::Vector2d(r[i].dot(s[i]), r[i].squaredNorm());
        });
        const double beta = rs[0] / rho;
        rho = rs[0];
        r2 = rs[1];
        ++result.iterations;
        if (r2 <= tol2) break;
        parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) p[i] = s[i] + beta * p[i];
        });
    }
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) dv[i] = x[i].head<3>();
    });
    result.relativeResidual = std::sqrt(r2 / rhsNorm2);
    result.converged = r2 <= tol2;
    return result;
}

} // namespace cc::cloth
