#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"

namespace cc::test {

/// A closed triangle mesh (CCW seen from outside) for collision tests.
struct BodyMesh {
    std::vector<Vec3> positions;
    std::vector<std::array<uint32_t, 3>> triangles;
};

/// A UV sphere of `radius` around `center`: `rings` latitude bands, `segments` longitudes, with
/// single pole vertices (so the mesh is closed and manifold).
inline BodyMesh uvSphere(const Vec3& center, double radius, uint32_t rings, uint32_t segments) {
    BodyMesh m;
    const double pi = 3.14159265358979323846;
    m.positions.push_back(center + Vec3(0, radius, 0));
    for (uint32_t r = 1; r < rings; ++r) {
        const double theta = pi * r / rings;
        for (uint32_t s = 0; s < segments; ++s) {
            const double phi = 2 * pi * s / segments;
            m.positions.push_back(center + radius * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                         -std::sin(theta) * std::sin(phi)));
        }
    }
    m.positions.push_back(center + Vec3(0, -radius, 0));
    const uint32_t south = uint32_t(m.positions.size() - 1);
    auto ring = [&](uint32_t r, uint32_t s) { return 1 + (r - 1) * segments + (s % segments); };
    for (uint32_t s = 0; s < segments; ++s) m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
    for (uint32_t r = 1; r + 1 < rings; ++r) {
        for (uint32_t s = 0; s < segments; ++s) {
            m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
            m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
        }
    }
    for (uint32_t s = 0; s < segments; ++s) m.triangles.push_back({ring(rings - 1, s), south, ring(rings - 1, s + 1)});
    return m;
}

/// A flat rectangle (two triangles per cell) through `origin` spanned by `u` and `v`, normal u x v.
inline BodyMesh grid(const Vec3& origin, const Vec3& u, const Vec3& v, uint32_t cells) {
    BodyMesh m;
    for (uint32_t j = 0; j <= cells; ++j) {
        for (uint32_t i = 0; i <= cells; ++i) m.positions.push_back(origin + u * (double(i) / cells) + v * (double(j) / cells));
    }
    auto at = [&](uint32_t i, uint32_t j) { return j * (cells + 1) + i; };
    for (uint32_t j = 0; j < cells; ++j) {
        for (uint32_t i = 0; i < cells; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return m;
}

/// Closest point of triangle abc to p, computed differently from the library (plane projection
/// when it falls inside, else the best of the three edges), as a brute-force oracle.
inline Vec3 bruteClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    auto onSegment = [&](const Vec3& s0, const Vec3& s1) {
        const Vec3 d = s1 - s0;
        const double len2 = d.squaredNorm();
        const double t = len2 > 0 ? std::clamp((p - s0).dot(d) / len2, 0.0, 1.0) : 0.0;
        return Vec3(s0 + t * d);
    };
    const Vec3 n = (b - a).cross(c - a);
    if (n.squaredNorm() > 0) {
        Vec3 q = p - n * ((p - a).dot(n) / n.squaredNorm());
        const bool in = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
        if (in) return q;
    }
    Vec3 best = onSegment(a, b);
    for (const Vec3& cand : {onSegment(b, c), onSegment(c, a)}) {
        if ((cand - p).squaredNorm() < (best - p).squaredNorm()) best = cand;
    }
    return best;
}

} // namespace cc::test
