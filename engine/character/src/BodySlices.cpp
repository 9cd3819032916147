#include "BodySlices.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace cc::detail {
namespace {

/// Where edge (a, b) crosses y = height, if it does (half-open in y so a vertex exactly on the plane
/// is counted once per edge pair, never twice).
bool crossing(const Vec3& a, const Vec3& b, double height, Vec2& out) {
    const bool aBelow = a.y() < height, bBelow = b.y() < height;
    if (aBelow == bBelow) return false;
    const double t = (height - a.y()) / (b.y() - a.y());
    out = Vec2(a.x() + t * (b.x() - a.x()), a.z() + t * (b.z() - a.z()));
    return true;
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

} // namespace

// A plane through a ring of vertices would cut it on one side only: generated meshes (and many
// modelled ones) have rings at round heights, so the plane is moved off them by a hair.
constexpr double kOffRing = 1e-7;

void slicePoints(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                 const std::vector<uint8_t>& keep, double height, std::vector<Vec2>& outPoints) {
    height += kOffRing;
    outPoints.clear();
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (!keep.empty() && !keep[t]) continue;
        const auto& tri = triangles[t];
        for (int k = 0; k < 3; ++k) {
            Vec2 p;
            if (crossing(positions[tri[k]], positions[tri[(k + 1) % 3]], height, p)) outPoints.push_back(p);
        }
    }
}

std::vector<uint32_t> samePositionIds(Span<const Vec3> positions) {
    std::vector<uint32_t> order(positions.size()), ids(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    const auto less = [&](uint32_t a, uint32_t b) {
        const Vec3& p = positions[a];
        const Vec3& q = positions[b];
        if (p.x() != q.x()) return p.x() < q.x();
        if (p.y() != q.y()) return p.y() < q.y();
        if (p.z() != q.z()) return p.z() < q.z();
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const bool same = i > 0 && positions[order[i]] == positions[order[i - 1]];
        ids[order[i]] = same ? ids[order[i - 1]] : order[i];
    }
    return ids;
}

void sliceLoops(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                const std::vector<uint8_t>& keep, const std::vector<uint32_t>& sameIds, double height,
                std::vector<SliceLoop>& outLoops) {
    height += kOffRing;
    outLoops.clear();
    // Cut triangles, their crossing points, and the edges they were found on.
    struct Cut {
        uint32_t triangle;
        std::array<Vec2, 2> points;
        std::array<uint64_t, 2> edges;
        int count = 0;
    };
    std::vector<Cut> cuts;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (!keep.empty() && !keep[t]) continue;
        const auto& tri = triangles[t];
        Cut cut;
        cut.triangle = uint32_t(t);
        for (int k = 0; k < 3 && cut.count < 2; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            Vec2 p;
            if (!crossing(positions[a], positions[b], height, p)) continue;
            const uint32_t ka = sameIds.empty() ? a : sameIds[a], kb = sameIds.empty() ? b : sameIds[b];
            cut.points[cut.count] = p;
            cut.edges[cut.count] = ka < kb ? (uint64_t(ka) << 32 | kb) : (uint64_t(kb) << 32 | ka);
            ++cut.count;
        }
        if (cut.count == 2) cuts.push_back(cut);
    }
    std::vector<uint32_t> parent(cuts.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::map<uint64_t, uint32_t> firstOnEdge;
    for (uint32_t c = 0; c < cuts.size(); ++c) {
        for (uint64_t e : cuts[c].edges) {
            auto [it, inserted] = firstOnEdge.emplace(e, c);
            if (!inserted) {
                const uint32_t a = findRoot(parent, it->second), b = findRoot(parent, c);
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
            }
        }
    }
    std::map<uint32_t, std::size_t> loopOf;
    for (uint32_t c = 0; c < cuts.size(); ++c) {
        const uint32_t root = findRoot(parent, c);
        auto [it, inserted] = loopOf.emplace(root, outLoops.size());
        if (inserted) outLoops.emplace_back();
        SliceLoop& loop = outLoops[it->second];
        loop.points.push_back(cuts[c].points[0]);
        loop.points.push_back(cuts[c].points[1]);
    }
    for (SliceLoop& loop : outLoops) {
        loop.centroid = Vec2::Zero();
        for (const Vec2& p : loop.points) loop.centroid += p;
        loop.centroid /= double(loop.points.size());
    }
}

double perimeter(const std::vector<Vec2>& polygon) {
    double length = 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i) length += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
    return polygon.size() < 2 ? 0.0 : length;
}

bool insideConvex(const std::vector<Vec2>& hull, const Vec2& p, double margin) {
    if (hull.size() < 3) return false;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec2& a = hull[i];
        const Vec2 edge = hull[(i + 1) % hull.size()] - a;
        const double length = edge.norm();
        if (length == 0.0) continue;
        // Signed distance to the edge's line, positive outside (the hull is CCW).
        const double outside = (edge.x() * (p.y() - a.y()) - edge.y() * (p.x() - a.x())) / -length;
        if (outside > margin) return false;
    }
    return true;
}

} // namespace cc::detail
