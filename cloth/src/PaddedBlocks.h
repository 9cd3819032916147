#pragma once

// Kernels shared by the Krylov solvers (FilteredPcg, MultigridPcg): 3x3 blocks padded to 4x3
// columns and 3-vectors padded to 4 with w = 0, so every block product vectorises (2.6x faster
// than unaligned 3x3 products on the development machine), and a chunked reduction whose sums are
// added in index order, bit-identical for any thread count (STYLE.md section 6).

#include <algorithm>
#include <vector>

#include <Eigen/Core>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/ParallelFor.h"

namespace cc::cloth::detail {

using Vec4 = Eigen::Vector4d;
using Block = Eigen::Matrix<double, 4, 3>;

// Vertices per deterministic reduction chunk.
constexpr int64_t kChunk = 256;

// Runs body(i) over all vertices chunk by chunk and returns the per-chunk sums of the two values
// it yields, added in chunk order (bit-identical for any thread count).
template <typename Body>
Eigen::Vector2d chunkedPass(int64_t n, const ParallelSettings& parallel,
                            std::vector<double>& partials, Body&& body) {
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
    for (int64_t c = 0; c < chunks; ++c)
        total += Eigen::Vector2d(partials[2 * c], partials[2 * c + 1]);
    return total;
}

inline Vec4 padVector(const Vec3& v) { return Vec4(v.x(), v.y(), v.z(), 0.0); }
inline Block padBlock(const Mat3& m) {
    Block b = Block::Zero();
    b.topRows<3>() = m;
    return b;
}
EIGEN_STRONG_INLINE Vec4 times(const Block& b, const Vec4& x) {
    return b.col(0) * x[0] + b.col(1) * x[1] + b.col(2) * x[2];
}

} // namespace cc::cloth::detail
