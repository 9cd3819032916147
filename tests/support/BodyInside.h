#pragma once
// An independent check of garments against the posed body, for the World tests: needs no BVH and
// no closest-point code of the collision module.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/core/Math.h"

namespace cc::test {

inline Vec3 vertexOf(const float* xyz, uint32_t v) { return Vec3(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]); }

/// Generalised winding number of a closed, outward-oriented triangle soup at p (Jacobson et al.
/// 2013): ~1 inside one closed part, ~k inside k overlapping parts, ~0 outside.
inline double windingNumber(const RenderMeshView& body, const Vec3& p) {
    double total = 0.0;
    for (uint32_t t = 0; t < body.triangleCount; ++t) {
        const Vec3 a = vertexOf(body.positions, body.indices[3 * t]) - p;
        const Vec3 b = vertexOf(body.positions, body.indices[3 * t + 1]) - p;
        const Vec3 c = vertexOf(body.positions, body.indices[3 * t + 2]) - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double numerator = a.dot(b.cross(c));
        const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * std::atan2(numerator, denominator);
    }
    return total / (4.0 * M_PI);
}

/// Distance from p to the body surface (brute force, Ericson's closest point by regions).
inline double distanceToSurface(const RenderMeshView& body, const Vec3& p) {
    double best = 1e30;
    for (uint32_t t = 0; t < body.triangleCount; ++t) {
        const Vec3 a = vertexOf(body.positions, body.indices[3 * t]);
        const Vec3 b = vertexOf(body.positions, body.indices[3 * t + 1]);
        const Vec3 c = vertexOf(body.positions, body.indices[3 * t + 2]);
        const Vec3 ab = b - a, ac = c - a, ap = p - a;
        const double d1 = ab.dot(ap), d2 = ac.dot(ap);
        const Vec3 bp = p - b, cp = p - c;
        const double d3 = ab.dot(bp), d4 = ac.dot(bp), d5 = ab.dot(cp), d6 = ac.dot(cp);
        const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        Vec3 q;
        if (d1 <= 0 && d2 <= 0) q = a;
        else if (d3 >= 0 && d4 <= d3) q = b;
        else if (d6 >= 0 && d5 <= d6) q = c;
        else if (vc <= 0 && d1 >= 0 && d3 <= 0) q = a + d1 / (d1 - d3) * ab;
        else if (vb <= 0 && d2 >= 0 && d6 <= 0) q = a + d2 / (d2 - d6) * ac;
        else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) q = b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
        else q = a + ab * (vb / (va + vb + vc)) + ac * (vc / (va + vb + vc));
        best = std::min(best, (p - q).norm());
    }
    return best;
}

/// Whether the segment pq crosses a triangle of the body (Moller & Trumbore 1997, brute force).
inline bool segmentCrossesBody(const RenderMeshView& body, const Vec3& p, const Vec3& q) {
    const Vec3 d = q - p;
    for (uint32_t t = 0; t < body.triangleCount; ++t) {
        const Vec3 a = vertexOf(body.positions, body.indices[3 * t]);
        const Vec3 e1 = vertexOf(body.positions, body.indices[3 * t + 1]) - a;
        const Vec3 e2 = vertexOf(body.positions, body.indices[3 * t + 2]) - a;
        const Vec3 h = d.cross(e2);
        const double det = e1.dot(h);
        if (std::abs(det) < 1e-14) continue;
        const Vec3 s = p - a, r = s.cross(e1);
        const double u = s.dot(h) / det, v = d.dot(r) / det, along = e2.dot(r) / det;
        if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && along > 0.0 && along < 1.0) return true;
    }
    return false;
}

/// The garment's render edges (each once) that cross the body's surface: cloth the body passes
/// through between two vertices.
inline int edgesThroughBody(const RenderMeshView& cloth, const RenderMeshView& body) {
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    for (uint32_t t = 0; t < cloth.triangleCount; ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = cloth.indices[3 * t + k], b = cloth.indices[3 * t + (k + 1) % 3];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    int crossing = 0;
    for (const auto& [a, b] : edges)
        crossing +=
            segmentCrossesBody(body, vertexOf(cloth.positions, a), vertexOf(cloth.positions, b));
    return crossing;
}

} // namespace cc::test
