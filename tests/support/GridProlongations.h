#pragma once

#include <vector>

#include "crowdcloth/core/RectanglePanel.h"
#include "crowdcloth/core/SparseInterpolation.h"

namespace cc::test {

/// The 4-8 hierarchy's level-to-level interpolation over a square RectanglePanel of 2^k squares
/// per side, finest first, as lod/ would hand it to the multigrid solver: a Union Jack level
/// drops its valence-4 vertices (each the midpoint of the axis edge along its odd coordinate), a
/// diamond level drops the centres of the coarse squares (each the midpoint of that square's
/// diagonal, which alternates like RectanglePanel's).
inline std::vector<SparseInterpolation> gridProlongations(const RectanglePanel& panel) {
    const int n = int(panel.columns);  // squares per side, a power of two
    const auto at = [&](int i, int j) { return j * (n + 1) + i; };
    std::vector<int> current;  // grid points of the current level, in its vertex order
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) current.push_back(at(i, j));
    std::vector<SparseInterpolation> levels;
    for (int step = 1; step < n; step *= 2) {
        for (bool diamond : {true, false}) {
            std::vector<int> index((n + 1) * (n + 1), -1), next;
            const auto kept = [&](int i, int j) {
                return diamond ? (i / step + j / step) % 2 == 0
                               : i % (2 * step) == 0 && j % (2 * step) == 0;
            };
            for (int v : current) {
                if (kept(v % (n + 1), v / (n + 1))) {
                    index[v] = int(next.size());
                    next.push_back(v);
                }
            }
            SparseInterpolation p;
            p.sourceCount = uint32_t(next.size());
            const auto term = [&](int i, int j) {
                p.terms.push_back({uint32_t(index[at(i, j)]), 0.5});
            };
            for (int v : current) {
                const int i = v % (n + 1), j = v / (n + 1), s = step;
                if (index[v] >= 0) {
                    p.terms.push_back({uint32_t(index[v]), 1.0});
                } else if (diamond && (i / s) % 2 == 1) {
                    term(i - s, j);
                    term(i + s, j);
                } else if (diamond) {
                    term(i, j - s);
                    term(i, j + s);
                } else if (((i - s) / (2 * s) + (j - s) / (2 * s)) % 2 == 0) {
                    term(i - s, j - s);
                    term(i + s, j + s);
                } else {
                    term(i + s, j - s);
                    term(i - s, j + s);
                }
                p.rowStart.push_back(uint32_t(p.terms.size()));
            }
            levels.push_back(std::move(p));
            current = std::move(next);
        }
    }
    return levels;
}

} // namespace cc::test
