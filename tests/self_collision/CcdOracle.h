#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "crowdcloth/core/Math.h"

// Brute-force reference for continuous queries, independent of collision/Ccd: exact Euclidean
// distances in long double, and a Lipschitz bound on the distance over time so that a whole
// interval can be proven clear.
namespace cc::test {

using LVec = Eigen::Matrix<long double, 3, 1>;

inline LVec toLong(const Vec3& v) { return v.cast<long double>(); }

inline long double pointSegmentDistance(const LVec& p, const LVec& a, const LVec& b) {
    const LVec ab = b - a;
    const long double len2 = ab.squaredNorm();
    long double s = len2 > 0 ? (p - a).dot(ab) / len2 : 0;
    s = std::clamp(s, 0.0L, 1.0L);
    return (a + s * ab - p).norm();
}

/// Distance from p to triangle abc: the plane projection when it falls inside, else the nearest edge.
inline long double pointTriangleDistance(const LVec& p, const LVec& a, const LVec& b, const LVec& c) {
    const LVec n = (b - a).cross(c - a);
    const long double n2 = n.squaredNorm();
    if (n2 > 0) {
        const LVec q = p - n * ((p - a).dot(n) / n2);
        // Signs of the sub-triangle areas tell whether q is inside.
        const long double s0 = (b - q).cross(c - q).dot(n);
        const long double s1 = (c - q).cross(a - q).dot(n);
        const long double s2 = (a - q).cross(b - q).dot(n);
        if (s0 >= 0 && s1 >= 0 && s2 >= 0) return std::fabs((p - a).dot(n)) / std::sqrt(n2);
    }
    return std::min({pointSegmentDistance(p, a, b), pointSegmentDistance(p, b, c), pointSegmentDistance(p, c, a)});
}

/// Distance between segments ab and cd: the interior stationary point of the convex quadratic
/// when it exists, else the best of the four endpoint-to-segment distances.
inline long double segmentSegmentDistance(const LVec& a, const LVec& b, const LVec& c, const LVec& d) {
    long double best = std::min({pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d),
                                 pointSegmentDistance(c, a, b), pointSegmentDistance(d, a, b)});
    const LVec e1 = b - a, e2 = d - c, r = a - c;
    const long double A = e1.dot(e1), B = e1.dot(e2), C = e2.dot(e2), D = e1.dot(r), E = e2.dot(r);
    const long double det = A * C - B * B;
    if (det > 1e-30L * A * C) {
        const long double s = (B * E - C * D) / det, u = (A * E - B * D) / det;
        if (s >= 0 && s <= 1 && u >= 0 && u <= 1) best = std::min(best, (a + s * e1 - c - u * e2).norm());
    }
    return best;
}

enum class OracleVerdict { Clear, Contact, Ambiguous };

struct OracleResult {
    OracleVerdict verdict = OracleVerdict::Ambiguous;
    long double firstContact = 1;  ///< earliest time found with distance <= thickness
    long double minDistance = 0;   ///< smallest sampled distance
};

/// Decides whether the distance between the two moving primitives reaches `thickness` over
/// t in [0, 1]: bisection, proving a sub-interval clear when even the Lipschitz bound keeps it
/// above the thickness. `vertexTriangle` selects p-abc, otherwise edges ab-cd.
inline OracleResult bruteForceCcd(bool vertexTriangle, const std::array<Vec3, 4>& start,
                                  const std::array<Vec3, 4>& end, double thickness) {
    std::array<LVec, 4> x0, dx;
    long double speed[4];
    for (int i = 0; i < 4; ++i) {
        x0[i] = toLong(start[i]);
        dx[i] = toLong(end[i]) - x0[i];
        speed[i] = dx[i].norm();
    }
    // Every point of a primitive moves at most as fast as its fastest vertex.
    const long double lipschitz = vertexTriangle
                                      ? speed[0] + std::max({speed[1], speed[2], speed[3]})
                                      : std::max(speed[0], speed[1]) + std::max(speed[2], speed[3]);
    auto distance = [&](long double t) {
        std::array<LVec, 4> x;
        for (int i = 0; i < 4; ++i) x[i] = x0[i] + t * dx[i];
        return vertexTriangle ? pointTriangleDistance(x[0], x[1], x[2], x[3])
                              : segmentSegmentDistance(x[0], x[1], x[2], x[3]);
    };
    // A touch at an isolated instant (zero thickness) is only hit by a sample exactly at that
    // instant; 1e-13 m of slack lets the bisection find it.
    const long double eta = thickness + 1e-13L;
    OracleResult result;
    result.minDistance = std::min(distance(0), distance(1));
    bool ambiguous = false;
    // Depth-first, earlier half first, so the first contact found is the earliest sampled one.
    struct Frame {
        long double t0, t1, d0, d1;
        int depth;
    };
    Frame stack[256];
    int top = 0;
    stack[top++] = {0, 1, distance(0), distance(1), 0};
    while (top > 0) {
        const Frame f = stack[--top];
        result.minDistance = std::min({result.minDistance, f.d0, f.d1});
        if (f.d0 <= eta) {
            result.verdict = OracleVerdict::Contact;
            result.firstContact = f.t0;
            return result;
        }
        if ((f.d0 + f.d1 - lipschitz * (f.t1 - f.t0)) / 2 > eta) continue;
        if (f.depth >= 60) {
            if (f.d1 <= eta) {
                result.verdict = OracleVerdict::Contact;
                result.firstContact = f.t1;
                return result;
            }
            ambiguous = true;
            continue;
        }
        const long double tm = (f.t0 + f.t1) / 2, dm = distance(tm);
        stack[top++] = {tm, f.t1, dm, f.d1, f.depth + 1};
        stack[top++] = {f.t0, tm, f.d0, dm, f.depth + 1};
    }
    result.verdict = ambiguous ? OracleVerdict::Ambiguous : OracleVerdict::Clear;
    return result;
}

} // namespace cc::test
