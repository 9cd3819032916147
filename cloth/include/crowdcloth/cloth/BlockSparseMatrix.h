#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Span.h"

namespace cc::cloth {

/// Square sparse matrix of 3x3 blocks in block-CSR form with a symmetric pattern (every row holds
/// its diagonal block). Rows are independent, so a product runs row-parallel and deterministic.
/// The pattern is built once per mesh; assembly writes into fixed slots.
class BlockSparseMatrix {
public:
    /// Builds the pattern for `size` block rows from vertex couplings (i, j), i != j; both (i, j)
    /// and (j, i) are stored. Values are zeroed.
    void buildPattern(uint32_t size, std::vector<std::pair<uint32_t, uint32_t>> couplings);

    uint32_t size() const { return static_cast<uint32_t>(mRowStart.size()) - 1; }
    std::size_t blockCount() const { return mBlocks.size(); }
    /// Slot of block (row, col); the block must be in the pattern.
    uint32_t slot(uint32_t row, uint32_t col) const;
    uint32_t diagonalSlot(uint32_t row) const { return mDiagonal[row]; }

    Mat3& block(uint32_t slot) { return mBlocks[slot]; }
    const Mat3& block(uint32_t slot) const { return mBlocks[slot]; }
    const std::vector<uint32_t>& rowStart() const { return mRowStart; }
    const std::vector<uint32_t>& columns() const { return mColumns; }

    void setZero(const ParallelSettings& parallel);
    /// out = this * x.
    void multiply(Span<const Vec3> x, Span<Vec3> out, const ParallelSettings& parallel) const;

private:
    std::vector<uint32_t> mRowStart{0};
    std::vector<uint32_t> mColumns;
    std::vector<uint32_t> mDiagonal;
    std::vector<Mat3> mBlocks;
};

} // namespace cc::cloth
