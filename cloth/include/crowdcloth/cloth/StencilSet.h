#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/cloth/BlockSparseMatrix.h"

namespace cc::cloth {

/// Elements that each touch N vertices (springs N=2, triangles N=3, hinges N=4), sorted into
/// colours so that no two elements of one colour share a vertex. A colour's elements can then
/// scatter into forces and matrix blocks in parallel without races, and every sum is taken in the
/// same order (colour by colour) for any thread count.
template <int N>
struct StencilSet {
    std::vector<std::array<uint32_t, N>> vertices;     ///< per element, after colour sorting
    std::vector<uint32_t> colourStart{0};              ///< element range [colourStart[c], colourStart[c+1])
    std::vector<std::array<uint32_t, N * N>> slots;    ///< matrix slot of block (a, b) at a*N+b

    std::size_t size() const { return vertices.size(); }
    std::size_t colourCount() const { return colourStart.size() - 1; }

    /// Greedy colouring in input order; returns the permutation applied (new -> old index), so
    /// callers can reorder their per-element data the same way.
    std::vector<uint32_t> colour(uint32_t vertexCount);
    /// Appends every coupled vertex pair, for the matrix pattern.
    void appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const;
    /// Looks up the matrix slot of every element block.
    void bindSlots(const BlockSparseMatrix& matrix);
};

/// Reorders `data` by a permutation from StencilSet::colour (new -> old).
template <typename T>
std::vector<T> permute(const std::vector<T>& data, const std::vector<uint32_t>& order) {
    std::vector<T> out;
    out.reserve(order.size());
    for (uint32_t old : order) out.push_back(data[old]);
    return out;
}

} // namespace cc::cloth
