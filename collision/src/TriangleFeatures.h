#pragma once

#include <array>

#include "crowdcloth/core/Math.h"

namespace cc::collision::detail {

/// The feature of a triangle a closest point lies on: the face, one of the vertices 0..2, or one
/// of the edges 0..2 (edge k joins vertex k and vertex (k + 1) % 3).
enum class Feature : uint8_t { Face, Vertex0, Vertex1, Vertex2, Edge0, Edge1, Edge2 };

struct ClosestPoint {
    Vec3 point;
    std::array<double, 3> weights;  // barycentric
    Feature feature;
};

/// Closest point of triangle abc to p by Voronoi regions (Ericson 2005, Real-Time Collision
/// Detection, 5.1.5), also naming the region so the caller can pick the matching pseudonormal.
inline ClosestPoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return {a, {1, 0, 0}, Feature::Vertex0};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return {b, {0, 1, 0}, Feature::Vertex1};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {a + v * ab, {1 - v, v, 0}, Feature::Edge0};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return {c, {0, 0, 1}, Feature::Vertex2};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {a + w * ac, {1 - w, 0, w}, Feature::Edge2};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {b + w * (c - b), {0, 1 - w, w}, Feature::Edge1};
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {a + ab * v + ac * w, {1 - v - w, v, w}, Feature::Face};
}

} // namespace cc::collision::detail
