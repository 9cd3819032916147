#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"

// Independent check of a mesh state: counts pairs of non-adjacent triangles that intersect, by
// segment-triangle crossing tests with orientation signs in long double (no CCD involved).
namespace cc::test {

inline long double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    using L = long double;
    const L ax = L(a.x()) - L(d.x()), ay = L(a.y()) - L(d.y()), az = L(a.z()) - L(d.z());
    const L bx = L(b.x()) - L(d.x()), by = L(b.y()) - L(d.y()), bz = L(b.z()) - L(d.z());
    const L cx = L(c.x()) - L(d.x()), cy = L(c.y()) - L(d.y()), cz = L(c.z()) - L(d.z());
    return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

/// Segment pq crosses (or touches) triangle abc; coplanar configurations are not counted.
/// `flat` [m^3] is the orientation volume below which an endpoint counts as in the plane: a flat
/// sheet's coplanar neighbours would otherwise cross on rounding noise.
inline bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                                   long double flat) {
    const long double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
    if (std::fabs(sp) <= flat && std::fabs(sq) <= flat) return false;  // coplanar: not counted
    if ((sp > 0 && sq > 0) || (sp < 0 && sq < 0)) return false;
    const long double e0 = orient(p, q, a, b), e1 = orient(p, q, b, c), e2 = orient(p, q, c, a);
    return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
}

/// Number of intersecting pairs of triangles that share no vertex.
inline int countIntersectingPairs(const std::vector<Vec3>& x, const std::vector<std::array<uint32_t, 3>>& tris) {
    const std::size_t n = tris.size();
    std::vector<Vec3> lo(n), hi(n);
    for (std::size_t t = 0; t < n; ++t) {
        lo[t] = x[tris[t][0]].cwiseMin(x[tris[t][1]]).cwiseMin(x[tris[t][2]]);
        hi[t] = x[tris[t][0]].cwiseMax(x[tris[t][1]]).cwiseMax(x[tris[t][2]]);
    }
    int count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            if ((lo[i].array() > hi[j].array()).any() || (lo[j].array() > hi[i].array()).any()) continue;
            const auto& A = tris[i];
            const auto& B = tris[j];
            bool adjacent = false;
            for (uint32_t a : A) adjacent = adjacent || a == B[0] || a == B[1] || a == B[2];
            if (adjacent) continue;
            const long double size = (hi[i].cwiseMax(hi[j]) - lo[i].cwiseMin(lo[j])).norm();
            const long double flat = 1e-12L * size * size * size;
            bool hit = false;
            for (int k = 0; k < 3 && !hit; ++k) {
                hit = segmentCrossesTriangle(x[A[k]], x[A[(k + 1) % 3]], x[B[0]], x[B[1]], x[B[2]], flat) ||
                      segmentCrossesTriangle(x[B[k]], x[B[(k + 1) % 3]], x[A[0]], x[A[1]], x[A[2]], flat);
            }
            count += hit ? 1 : 0;
        }
    }
    return count;
}

} // namespace cc::test
