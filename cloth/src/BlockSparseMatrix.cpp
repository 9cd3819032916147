#include "crowdcloth/cloth/BlockSparseMatrix.h"

#include <algorithm>

namespace cc::cloth {

void BlockSparseMatrix::buildPattern(uint32_t n, std::vector<std::pair<uint32_t, uint32_t>> couplings) {
    const std::size_t m = couplings.size();
    for (std::size_t k = 0; k < m; ++k) couplings.emplace_back(couplings[k].second, couplings[k].first);
    for (uint32_t i = 0; i < n; ++i) couplings.emplace_back(i, i);
    std::sort(couplings.begin(), couplings.end());
    couplings.erase(std::unique(couplings.begin(), couplings.end()), couplings.end());

    mRowStart.assign(n + 1, 0);
    mColumns.resize(couplings.size());
    mDiagonal.resize(n);
    for (std::size_t k = 0; k < couplings.size(); ++k) {
        const auto [row, col] = couplings[k];
        ++mRowStart[row + 1];
        mColumns[k] = col;
        if (row == col) mDiagonal[row] = static_cast<uint32_t>(k);
    }
    for (uint32_t i = 0; i < n; ++i) mRowStart[i + 1] += mRowStart[i];
    mBlocks.assign(couplings.size(), Mat3::Zero());
}

uint32_t BlockSparseMatrix::slot(uint32_t row, uint32_t col) const {
    const auto first = mColumns.begin() + mRowStart[row];
    const auto last = mColumns.begin() + mRowStart[row + 1];
    return static_cast<uint32_t>(std::lower_bound(first, last, col) - mColumns.begin());
}

void BlockSparseMatrix::setZero(const ParallelSettings& parallel) {
    parallelFor(static_cast<int64_t>(mBlocks.size()), parallel, [&](int64_t b, int64_t e) {
        for (int64_t k = b; k < e; ++k) mBlocks[k].setZero();
    });
}

void BlockSparseMatrix::multiply(Span<const Vec3> x, Span<Vec3> out, const ParallelSettings& parallel) const {
    parallelFor(size(), parallel, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            Vec3 sum = Vec3::Zero();
            for (uint32_t k = mRowStart[i]; k < mRowStart[i + 1]; ++k) sum += mBlocks[k] * x[mColumns[k]];
            out[i] = sum;
        }
    });
}

} // namespace cc::cloth
