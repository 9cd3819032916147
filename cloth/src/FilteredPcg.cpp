#include "crowdcloth/cloth/FilteredPcg.h"

#include <cmath>

namespace cc::cloth {
namespace {

// Vertices per deterministic reduction chunk.
constexpr int64_t kChunk = 256;

// Runs body(i) over all vertices chunk by chunk and returns the per-chunk sums of the up to two
// values it yields, added in chunk order.
template <typename Body>
Eigen::Vector2d chunkedPass(int64_t n, const ParallelSettings& parallel, std::vector<double>& partials, Body&& body) {
    const int64_t chunks = (n + kChunk - 1) / kChunk;
    partials.resize(2 * chunks);
    ParallelSettings byChunk = parallel;
    byChunk.minParallel = std::max<int64_t>(1, parallel.minParallel / kChunk);
    parallelFor(chunks, byChunk, [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
            Eigen::Vector2d sum = Eigen::Vector2d::Zero();
            const int64_t end = std::min(n, (c + 1) * kChunk);
            for (int64_t i = c * kChunk; i < end; ++i) sum += body(i);
            partials[2 * c] = sum[0];
            partials[2 * c + 1] = sum[1];
        }
    });
    Eigen::Vector2d total = Eigen::Vector2d::Zero();
    for (int64_t c = 0; c < chunks; ++c) total += Eigen::Vector2d(partials[2 * c], partials[2 * c + 1]);
    return total;
}

Vec3 rowTimes(const BlockSparseMatrix& a, int64_t i, const std::vector<Vec3>& x) {
    const auto& start = a.rowStart();
    const auto& cols = a.columns();
    Vec3 sum = Vec3::Zero();
    for (uint32_t k = start[i]; k < start[i + 1]; ++k) sum.noalias() += a.block(k) * x[cols[k]];
    return sum;
}

} // namespace

double pcgBytesPerVertexIteration(double blocksPerRow) {
    // Product pass: blocks (72 B) + column indices (4 B) per block, row start (4 B), gather of the
    // direction (24 B per block, mostly cache hits: counted once), product write (24 B).
    const double product = blocksPerRow * (72.0 + 4.0) + 4.0 + 24.0 + 24.0;
    // Update pass: read dv, r, direction, product, inverse diagonal (72 B); write dv, r, z.
    const double update = 4 * 24.0 + 72.0 + 3 * 24.0;
    // Direction pass: read z, direction; write direction.
    const double direction = 3 * 24.0;
    return product + update + direction;
}

PcgResult solveFilteredPcg(const BlockSparseMatrix& a, const std::vector<VertexFilter>& f,
                           const std::vector<Vec3>& b, const std::vector<Vec3>& z, std::vector<Vec3>& dv,
                           const PcgSettings& settings, const ParallelSettings& parallel, PcgWorkspace& w) {
    const int64_t n = a.size();
    w.residual.resize(n);
    w.direction.resize(n);
    w.product.resize(n);
    w.preconditioned.resize(n);
    w.inverseDiagonal.resize(n);
    auto& r = w.residual;
    auto& p = w.direction;
    auto& q = w.product;
    auto& s = w.preconditioned;

    // Start from the warm guess with its constrained part replaced by z; the right-hand side norm
    // |S (b - A z)| sets the scale of the tolerance.
    parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
        for (int64_t i = i0; i < i1; ++i) {
            dv[i] = z[i] + f[i].project(dv[i] - z[i]);
            w.inverseDiagonal[i] = a.block(a.diagonalSlot(uint32_t(i))).inverse();
        }
    });
    const double rhsNorm2 = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
        const Vec3 c = f[i].project(b[i] - rowTimes(a, i, z));
        return Eigen::Vector2d(c.squaredNorm(), 0.0);
    })[0];
    PcgResult result;
    if (rhsNorm2 == 0.0) {
        dv = z;
        return result;
    }
    Eigen::Vector2d rs = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
        r[i] = f[i].project(b[i] - rowTimes(a, i, dv));
        s[i] = f[i].project(w.inverseDiagonal[i] * r[i]);
        p[i] = s[i];
        return Eigen::Vector2d(r[i].dot(s[i]), r[i].squaredNorm());
    });
    const double tol2 = settings.relativeTolerance * settings.relativeTolerance * rhsNorm2;
    double rho = rs[0];
    double r2 = rs[1];
    while (r2 > tol2 && result.iterations < settings.maxIterations) {
        const double pq = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
            q[i] = f[i].project(rowTimes(a, i, p));
            return Eigen::Vector2d(p[i].dot(q[i]), 0.0);
        })[0];
        if (!(pq > 0.0)) break;  // direction of zero curvature: nothing more to gain (or not SPD)
        const double alpha = rho / pq;
        rs = chunkedPass(n, parallel, w.partials, [&](int64_t i) {
            dv[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            s[i] = f[i].project(w.inverseDiagonal[i] * r[i]);
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
    result.relativeResidual = std::sqrt(r2 / rhsNorm2);
    result.converged = r2 <= tol2;
    return result;
}

} // namespace cc::cloth
