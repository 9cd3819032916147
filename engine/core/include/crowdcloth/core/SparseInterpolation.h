#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"

namespace cc {

/// A sparse linear map from source vertices to target vertices, row by row: target r is
/// sum_k weight_k * source[index_k] over terms [rowStart[r], rowStart[r + 1]). lod/ produces it
/// (render mesh from the simulated mesh, fine level from coarse level); a multigrid preconditioner
/// can use it as a prolongation and its transpose as a restriction.
struct SparseInterpolation {
    struct Term {
        uint32_t source;  ///< source vertex index
        double weight;    ///< [-] weights of a row sum to 1 for interpolation
    };
    std::vector<uint32_t> rowStart{0};  ///< size rowCount() + 1
    std::vector<Term> terms;
    uint32_t sourceCount = 0;           ///< number of source vertices the indices refer to

    uint32_t rowCount() const { return static_cast<uint32_t>(rowStart.size() - 1); }

    /// outTarget[r] = sum of weight * source over row r. `source` must have sourceCount entries.
    void apply(Span<const Vec3> source, std::vector<Vec3>& outTarget) const {
        outTarget.resize(rowCount());
        for (uint32_t r = 0; r < rowCount(); ++r) {
            Vec3 sum = Vec3::Zero();
            for (uint32_t k = rowStart[r]; k < rowStart[r + 1]; ++k) sum += terms[k].weight * source[terms[k].source];
            outTarget[r] = sum;
        }
    }
};

} // namespace cc
