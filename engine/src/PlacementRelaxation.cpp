#include "PlacementRelaxation.h"

#include <algorithm>
#include <cstddef>

namespace cc::detail {
namespace {

using Grid = std::vector<std::vector<Vec3>>;  // [row][column], row 0 the top (t = 1)

/// Rest positions of a panel's grid points, laid out as its placement grid.
std::vector<std::vector<Vec2>> restGrid(const lod::PanelDesc& panel, std::size_t rows, std::size_t columns) {
    std::vector<std::vector<Vec2>> rest(rows, std::vector<Vec2>(columns));
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c)
            rest[r][c] = panel.localRest(double(c) / double(columns - 1), 1.0 - double(r) / double(rows - 1));
    return rest;
}

/// Moves `moved` towards `anchor` until they are at most `length` apart.
void pullWithin(const Vec3& anchor, double length, Vec3& moved) {
    const Vec3 d = moved - anchor;
    const double n = d.norm();
    if (n > length) moved = anchor + d * (length / n);
}

/// The same for an edge whose ends both move, each half the way.
void shortenTo(double length, Vec3& a, Vec3& b) {
    const Vec3 d = b - a;
    const double n = d.norm();
    if (!(n > length)) return;
    const Vec3 half = 0.5 * (n - length) / n * d;
    a += half;
    b -= half;
}

/// Grid point k along a panel side, in the pattern's order along that side (v up the left and
/// right sides, u along the top and bottom).
Vec3& sidePoint(Grid& g, lod::PanelSide side, std::size_t k) {
    const std::size_t rows = g.size(), columns = g[0].size();
    switch (side) {
    case lod::PanelSide::Bottom: return g[rows - 1][k];
    case lod::PanelSide::Top: return g[0][k];
    case lod::PanelSide::Left: return g[rows - 1 - k][0];
    case lod::PanelSide::Right: break;
    }
    return g[rows - 1 - k][columns - 1];
}

std::size_t sideLength(const Grid& g, lod::PanelSide side) {
    return side == lod::PanelSide::Bottom || side == lod::PanelSide::Top ? g[0].size() : g.size();
}

/// One top-down sweep over a panel: each row pulled within reach of the row above, then its own
/// edges shortened; the wrap of a tube (last column = first) kept closed.
void sweep(const std::vector<std::vector<Vec2>>& rest, bool wraps, Grid& p) {
    const std::size_t rows = p.size(), columns = p[0].size();
    const auto length = [&](std::size_t r0, std::size_t c0, std::size_t r1, std::size_t c1) {
        return (rest[r0][c0] - rest[r1][c1]).norm();
    };
    for (std::size_t r = 1; r < rows; ++r) {
        for (std::size_t c = 0; c < columns; ++c) {
            pullWithin(p[r - 1][c], length(r - 1, c, r, c), p[r][c]);
            if (c > 0) pullWithin(p[r - 1][c - 1], length(r - 1, c - 1, r, c), p[r][c]);
            if (c + 1 < columns) pullWithin(p[r - 1][c + 1], length(r - 1, c + 1, r, c), p[r][c]);
        }
        for (std::size_t c = 0; c + 1 < columns; ++c) shortenTo(length(r, c, r, c + 1), p[r][c], p[r][c + 1]);
        if (wraps) p[r][columns - 1] = p[r][0] = 0.5 * (p[r][0] + p[r][columns - 1]);
    }
}

} // namespace

void relaxPlacement(const lod::GarmentPattern& pattern, std::vector<PanelPlacement>& placement) {
    std::vector<std::vector<std::vector<Vec2>>> rest(placement.size());
    for (std::size_t p = 0; p < placement.size(); ++p) {
        const Grid& g = placement[p].rings;
        if (g.size() < 2 || g[0].size() < 2) return;
        rest[p] = restGrid(pattern.panels[p], g.size(), g[0].size());
    }
    // Measured over the mannequin and three humanoids, every kind and cut: from 8 to 32 sweeps
    // (and four row passes each) the largest strain left falls by at most 7 points (a poncho's
    // 15 -> 8 %); what remains is where rows must wrap an arm or a shoulder.
    constexpr int kSweeps = 8;
    for (int s = 0; s < kSweeps; ++s) {
        for (std::size_t p = 0; p < placement.size(); ++p)
            sweep(rest[p], pattern.panels[p].shape == lod::PanelShape::Tube, placement[p].rings);
        for (const lod::Seam& seam : pattern.seams) {
            Grid& a = placement[seam.panelA].rings;
            Grid& b = placement[seam.panelB].rings;
            const std::size_t n = sideLength(a, seam.sideA);
            if (n != sideLength(b, seam.sideB)) continue;
            for (std::size_t k = 0; k < n; ++k) {
                Vec3& pa = sidePoint(a, seam.sideA, k);
                Vec3& pb = sidePoint(b, seam.sideB, seam.reversed ? n - 1 - k : k);
                pa = pb = 0.5 * (pa + pb);
            }
        }
    }
}

} // namespace cc::detail
