#include "crowdcloth/cloth/StencilSet.h"

#include <algorithm>
#include <numeric>

namespace cc::cloth {

template <int N>
std::vector<uint32_t> StencilSet<N>::colour(uint32_t vertexCount) {
    // Per vertex, a bit mask of colours already used by elements touching it (up to 64 colours,
    // then a slower list). Cloth valences keep this under ~30.
    std::vector<std::vector<uint32_t>> used(vertexCount);
    std::vector<uint32_t> colourOf(vertices.size());
    uint32_t colours = 0;
    for (std::size_t e = 0; e < vertices.size(); ++e) {
        uint32_t c = 0;
        for (;; ++c) {
            bool free = true;
            for (uint32_t v : vertices[e]) {
                if (std::find(used[v].begin(), used[v].end(), c) != used[v].end()) {
                    free = false;
                    break;
                }
            }
            if (free) break;
        }
        colourOf[e] = c;
        colours = std::max(colours, c + 1);
        for (uint32_t v : vertices[e]) used[v].push_back(c);
    }
    std::vector<uint32_t> order(vertices.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return colourOf[a] < colourOf[b]; });
    vertices = permute(vertices, order);
    colourStart.assign(colours + 1, 0);
    for (uint32_t c : colourOf) ++colourStart[c + 1];
    for (uint32_t c = 0; c < colours; ++c) colourStart[c + 1] += colourStart[c];
    slots.clear();
    return order;
}

template <int N>
void StencilSet<N>::appendCouplings(std::vector<std::pair<uint32_t, uint32_t>>& out) const {
    for (const auto& el : vertices) {
        for (int a = 0; a < N; ++a) {
            for (int b = a + 1; b < N; ++b) out.emplace_back(el[a], el[b]);
        }
    }
}

template <int N>
void StencilSet<N>::bindSlots(const BlockSparseMatrix& matrix) {
    slots.resize(vertices.size());
    for (std::size_t e = 0; e < vertices.size(); ++e) {
        for (int a = 0; a < N; ++a) {
            for (int b = 0; b < N; ++b) slots[e][a * N + b] = matrix.slot(vertices[e][a], vertices[e][b]);
        }
    }
}

template struct StencilSet<2>;
template struct StencilSet<3>;
template struct StencilSet<4>;

} // namespace cc::cloth
