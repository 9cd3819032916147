#include "crowdcloth/collision/Ccd.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

namespace cc::collision {

Status CcdSettings::validate() const {
    if (!(thickness >= 0.0) || !std::isfinite(thickness)) {
        return Status::invalidArgument("CcdSettings.thickness must be finite and >= 0, got " +
                                       std::to_string(thickness));
    }
    if (!(distanceTolerance > 0.0) || !std::isfinite(distanceTolerance)) {
        return Status::invalidArgument("CcdSettings.distanceTolerance must be finite and > 0, got " +
                                       std::to_string(distanceTolerance));
    }
    if (!(timeTolerance > 0.0) || !(timeTolerance < 1.0)) {
        return Status::invalidArgument("CcdSettings.timeTolerance must be in (0, 1), got " +
                                       std::to_string(timeTolerance));
    }
    if (maxBoxes < 1) {
        return Status::invalidArgument("CcdSettings.maxBoxes must be >= 1, got " + std::to_string(maxBoxes));
    }
    return Status::ok();
}

std::array<double, 3> closestTriangleWeights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Voronoi regions of the vertices, then the edges, then the face (Ericson 2005, 5.1.5).
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {1.0 - v, v, 0.0};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {1.0 - w, 0.0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0.0, 1.0 - w, w};
    }
    const double denom = va + vb + vc;
    if (denom > 0.0 && std::isfinite(denom)) {
        const double v = vb / denom, w = vc / denom;
        return {1.0 - v - w, v, w};
    }
    // A degenerate (zero-area) triangle: its closest point lies on one of its edges.
    std::array<double, 3> best{1.0, 0.0, 0.0};
    double bestDist = ap.squaredNorm();
    const Vec3* corners[3] = {&a, &b, &c};
    for (int e = 0; e < 3; ++e) {
        const Vec3& x = *corners[e];
        const Vec3& y = *corners[(e + 1) % 3];
        const Vec3 xy = y - x;
        const double len2 = xy.squaredNorm();
        const double s = len2 > 0.0 ? std::clamp((p - x).dot(xy) / len2, 0.0, 1.0) : 0.0;
        const double dist = (x + s * xy - p).squaredNorm();
        if (dist < bestDist) {
            bestDist = dist;
            best = {0.0, 0.0, 0.0};
            best[e] = 1.0 - s;
            best[(e + 1) % 3] = s;
        }
    }
    return best;
}

std::array<double, 2> closestSegmentParameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // Ericson 2005, 5.1.9: minimise over s, then clamp and re-solve for the other parameter.
    const Vec3 d1 = b - a, d2 = d - c, r = a - c;
    const double aa = d1.squaredNorm(), ee = d2.squaredNorm(), f = d2.dot(r);
    if (aa <= DBL_MIN && ee <= DBL_MIN) return {0.0, 0.0};
    if (aa <= DBL_MIN) return {0.0, std::clamp(f / ee, 0.0, 1.0)};
    const double cc = d1.dot(r);
    if (ee <= DBL_MIN) return {std::clamp(-cc / aa, 0.0, 1.0), 0.0};
    const double bb = d1.dot(d2);
    const double denom = aa * ee - bb * bb;
    // Parallel within rounding: any s works, take 0.
    double s = denom > 1e-14 * aa * ee ? std::clamp((bb * f - cc * ee) / denom, 0.0, 1.0) : 0.0;
    double u = (bb * s + f) / ee;
    if (u < 0.0) {
        u = 0.0;
        s = std::clamp(-cc / aa, 0.0, 1.0);
    } else if (u > 1.0) {
        u = 1.0;
        s = std::clamp((bb - cc) / aa, 0.0, 1.0);
    }
    return {s, u};
}

bool interiorClosestSegmentParameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                      std::array<double, 2>& out) {
    // The lines' closest points are at (s, u) = (bb f - cc ee, aa f - bb cc) / denom. The distance
    // is a convex quadratic in (s, u), so where that point is outside the unit square the segments'
    // closest points are on its boundary, at an end of an edge, and closestSegmentParameters()
    // clamps a parameter to 0 or 1. Decided here only for edges far from parallel (the point then
    // moves by far less than the tolerance under rounding) and points outside by more than it;
    // the rest take closestSegmentParameters()'s own values and test.
    const Vec3 d1 = b - a, d2 = d - c, r = a - c;
    const double aa = d1.squaredNorm(), ee = d2.squaredNorm();
    const double f = d2.dot(r), cc = d1.dot(r), bb = d1.dot(d2);
    const double denom = aa * ee - bb * bb;
    if (aa > DBL_MIN && ee > DBL_MIN && denom > 1e-6 * aa * ee) {
        const double sNumerator = bb * f - cc * ee, uNumerator = aa * f - bb * cc;
        const double tolerance = 1e-6 * denom;
        if (sNumerator < -tolerance || sNumerator > denom + tolerance || uNumerator < -tolerance ||
            uNumerator > denom + tolerance)
            return false;
    }
    const std::array<double, 2> su = closestSegmentParameters(a, b, c, d);
    if (!(su[0] > 0.0 && su[0] < 1.0 && su[1] > 0.0 && su[1] < 1.0)) return false;
    out = su;
    return true;
}

namespace {

enum class Pair { VertexTriangle, EdgeEdge };

/// A box of the search domain (t, u, v); for edge-edge u = s on ab and v = u on cd.
struct SearchBox {
    double t0, t1, u0, u1, v0, v1;
};

/// Min-heap order: earliest time first, then fixed tie-breaks so the search order never depends on
/// anything but the input.
struct LaterBox {
    bool operator()(const SearchBox& x, const SearchBox& y) const {
        if (x.t0 != y.t0) return x.t0 > y.t0;
        if (x.u0 != y.u0) return x.u0 > y.u0;
        return x.v0 > y.v0;
    }
};

class InclusionSearch {
public:
    InclusionSearch(Pair pair, const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end)
        : mPair(pair), mStart(start) {
        double scale = 0.0;
        for (int i = 0; i < 4; ++i) {
            mMotion[i] = end[i] - start[i];
            scale = std::max(scale, start[i].cwiseAbs().maxCoeff() + mMotion[i].cwiseAbs().maxCoeff());
        }
        mScale = scale;
        // Each corner value is a handful of roundings of numbers below 6 * scale; 64 ulps of the
        // scale bounds the accumulated error with room to spare, so no box is wrongly discarded.
        mRoundoff = 64.0 * DBL_EPSILON * scale;
    }

    double scale() const { return mScale; }
    double roundoff() const { return mRoundoff; }

    /// F = D + u E1 + v E2 at time t, the pair's separation vector as a multilinear function.
    void terms(double t, Vec3& outD, Vec3& outE1, Vec3& outE2) const {
        const Vec3 x0 = mStart[0] + t * mMotion[0];
        const Vec3 x1 = mStart[1] + t * mMotion[1];
        const Vec3 x2 = mStart[2] + t * mMotion[2];
        const Vec3 x3 = mStart[3] + t * mMotion[3];
        if (mPair == Pair::VertexTriangle) {  // p - a - u (b - a) - v (c - a)
            outD = x0 - x1;
            outE1 = x1 - x2;
            outE2 = x1 - x3;
        } else {  // a + s (b - a) - c - u (d - c)
            outD = x0 - x2;
            outE1 = x1 - x0;
            outE2 = x2 - x3;
        }
    }

    /// The 8 corner values of F over the box, index (it << 2) | (iu << 1) | iv.
    void corners(const SearchBox& box, std::array<Vec3, 8>& outF) const {
        const double ts[2] = {box.t0, box.t1}, us[2] = {box.u0, box.u1}, vs[2] = {box.v0, box.v1};
        for (int it = 0; it < 2; ++it) {
            Vec3 d, e1, e2;
            terms(ts[it], d, e1, e2);
            for (int iu = 0; iu < 2; ++iu) {
                for (int iv = 0; iv < 2; ++iv) outF[(it << 2) | (iu << 1) | iv] = d + us[iu] * e1 + vs[iv] * e2;
            }
        }
    }

    Vec3 position(int i, double t) const { return mStart[i] + t * mMotion[i]; }
    const Vec3& start(int i) const { return mStart[i]; }
    const Vec3& motion(int i) const { return mMotion[i]; }

private:
    Pair mPair;
    const std::array<Vec3, 4>& mStart;
    std::array<Vec3, 4> mMotion;
    double mScale = 0.0;
    double mRoundoff = 0.0;
};

enum class BoxVerdict { Excluded, Resolved, Split };

/// Classifies a box by the bounding box of F's corner values against the cube [-eta, eta]^3, and
/// picks the split direction that shrinks that bounding box most (Wang et al. 2021, section 5).
struct SearchLimits {
    double eta;            ///< [m] thickness plus the rounding bound: what may not be discarded
    double certain;        ///< [m] thickness minus the rounding bound: a corner this close is contact
    double tolerance;      ///< [m] spatial resolution
    double timeTolerance;  ///< [-] time resolution
    bool vertexTriangle;   ///< (u, v) must also satisfy u + v <= 1
};

/// |F|inf <= certain at a corner with valid parameters: a contact that surely happens.
bool isWitness(const Vec3& f, double u, double v, const SearchLimits& limits) {
    if (limits.vertexTriangle && u + v > 1.0) return false;
    return f.cwiseAbs().maxCoeff() <= limits.certain;
}

BoxVerdict classify(const InclusionSearch& search, const SearchBox& box, const SearchLimits& limits,
                    double& inOutWitness, int& outSplitAxis) {
    const double eta = limits.eta, tolerance = limits.tolerance;
    std::array<Vec3, 8> f;
    search.corners(box, f);
    Vec3 lo = f[0], hi = f[0];
    for (int i = 1; i < 8; ++i) {
        lo = lo.cwiseMin(f[i]);
        hi = hi.cwiseMax(f[i]);
    }
    // Only coordinates whose range straddles the cube's faces are undecided: a coordinate wholly
    // inside [-eta, eta] is satisfied everywhere on the box and needs no refinement.
    bool undecided[3];
    double undecidedExtent = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (lo[k] > eta || hi[k] < -eta) return BoxVerdict::Excluded;
        undecided[k] = lo[k] < -eta || hi[k] > eta;
        if (undecided[k]) undecidedExtent = std::max(undecidedExtent, hi[k] - lo[k]);
    }
    // The earliest corner in certain contact bounds the time of impact from above: boxes that start
    // after it need no search.
    {
        const double ts[2] = {box.t0, box.t1}, us[2] = {box.u0, box.u1}, vs[2] = {box.v0, box.v1};
        for (int i = 0; i < 8; ++i) {
            const double t = ts[i >> 2];
            if (t < inOutWitness && isWitness(f[i], us[(i >> 1) & 1], vs[i & 1], limits)) inOutWitness = t;
        }
    }
    if (undecidedExtent <= tolerance) return BoxVerdict::Resolved;
    if (box.t1 - box.t0 <= limits.timeTolerance && inOutWitness <= box.t1) return BoxVerdict::Resolved;
    // Width of F's change along each parameter, over the box's 4 edges in that direction, in the
    // undecided coordinates.
    double widths[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 8; ++i) {
        for (int axis = 0; axis < 3; ++axis) {
            const int bit = 4 >> axis;  // t is bit 2, u bit 1, v bit 0
            if (i & bit) continue;
            const Vec3 change = (f[i | bit] - f[i]).cwiseAbs();
            for (int k = 0; k < 3; ++k) {
                if (undecided[k]) widths[axis] = std::max(widths[axis], change[k]);
            }
        }
    }
    // Once the time is resolved, what is left undecided is the motion within that instant: accept
    // when the spatial parameters are resolved too, otherwise refine only them. Refining time
    // further would only chase the box's boundary at the tolerance scale (the cost blows up along
    // every contact boundary, e.g. parallel edges) without moving the time of impact.
    if (box.t1 - box.t0 <= limits.timeTolerance) {
        if (std::max(widths[1], widths[2]) <= tolerance) return BoxVerdict::Resolved;
        outSplitAxis = widths[1] >= widths[2] ? 1 : 2;
        return BoxVerdict::Split;
    }
    // Prefer a split that discards a half, time first (it moves the earliest box forward), then
    // the widest. Splitting by width alone refines every box along a contact boundary (parallel
    // edges, a point sliding onto a degenerate face) down to the time resolution, which costs
    // millions of boxes. F is multilinear, so its values at a half's new corners are averages of
    // the box's corners; this choice is a heuristic only, exclusion itself is re-evaluated.
    bool splitExcludes[3] = {false, false, false};
    for (int axis = 0; axis < 3; ++axis) {
        const int bit = 4 >> axis;
        for (int half = 0; half < 2 && !splitExcludes[axis]; ++half) {
            Vec3 hlo = Vec3::Constant(DBL_MAX), hhi = Vec3::Constant(-DBL_MAX);
            for (int i = 0; i < 8; ++i) {
                if (i & bit) continue;
                const Vec3 mid = 0.5 * (f[i] + f[i | bit]);
                const Vec3& corner = half == 0 ? f[i] : f[i | bit];
                hlo = hlo.cwiseMin(mid).cwiseMin(corner);
                hhi = hhi.cwiseMax(mid).cwiseMax(corner);
            }
            for (int k = 0; k < 3; ++k) {
                if (hlo[k] > eta || hhi[k] < -eta) splitExcludes[axis] = true;
            }
        }
    }
    // A certain contact at the middle time makes the later half irrelevant: as good as discarding it.
    {
        const double us[2] = {box.u0, box.u1}, vs[2] = {box.v0, box.v1};
        for (int i = 0; i < 4 && !splitExcludes[0]; ++i) {
            const Vec3 mid = 0.5 * (f[i] + f[i | 4]);
            if (isWitness(mid, us[(i >> 1) & 1], vs[i & 1], limits)) splitExcludes[0] = true;
        }
    }
    outSplitAxis = -1;
    if (splitExcludes[0] && widths[0] > 0.0) {
        outSplitAxis = 0;
    } else {
        for (int axis = 1; axis < 3; ++axis) {
            if (splitExcludes[axis] && widths[axis] > 0.0 &&
                (outSplitAxis < 0 || widths[axis] > widths[outSplitAxis])) {
                outSplitAxis = axis;
            }
        }
    }
    if (outSplitAxis < 0) {
        outSplitAxis = 0;
        for (int axis = 1; axis < 3; ++axis) {
            if (widths[axis] > widths[outSplitAxis]) outSplitAxis = axis;
        }
    }
    return BoxVerdict::Split;
}

bool allFinite(const std::array<Vec3, 4>& a, const std::array<Vec3, 4>& b) {
    for (int i = 0; i < 4; ++i) {
        if (!isFinite(a[i]) || !isFinite(b[i])) return false;
    }
    return true;
}

/// Orients `n` (non-zero) so that it separates: against the relative approach, or along the offset
/// at the start of the motion.
Vec3 orientNormal(Vec3 n, const Vec3& startOffset, const Vec3& relativeMotion) {
    n.normalize();
    const double side = startOffset.dot(n);
    if (side < 0.0) return -n;
    if (side > 0.0) return n;
    return relativeMotion.dot(n) > 0.0 ? -n : n;
}

/// A unit normal from closest points `offset` = first - second at the time of impact, falling back
/// to the primitives' own plane (`cross`) and then to the start offset and the motion when the
/// closest points coincide (vertex on the face, crossing edges, zero motion).
Vec3 contactNormal(const Vec3& offset, const Vec3& cross, const Vec3& startOffset, const Vec3& relativeMotion,
                   double noise) {
    const double len = offset.norm();
    if (len > noise) return offset / len;
    if (cross.norm() > noise * noise) return orientNormal(cross, startOffset, relativeMotion);
    if (startOffset.norm() > noise) return startOffset.normalized();
    if (relativeMotion.norm() > noise) return -relativeMotion.normalized();
    return Vec3::UnitY();
}

void fillHit(Pair pair, const InclusionSearch& search, double toi, CcdHit& outHit) {
    outHit.toi = toi;
    const double noise = std::max(search.roundoff(), 1e3 * DBL_EPSILON * search.scale());
    const Vec3 x0 = search.position(0, toi), x1 = search.position(1, toi);
    const Vec3 x2 = search.position(2, toi), x3 = search.position(3, toi);
    if (pair == Pair::VertexTriangle) {
        const std::array<double, 3> w = closestTriangleWeights(x0, x1, x2, x3);
        outHit.weights = w;
        const Vec3 q = w[0] * x1 + w[1] * x2 + w[2] * x3;
        const Vec3 q0 = w[0] * search.start(1) + w[1] * search.start(2) + w[2] * search.start(3);
        const Vec3 qMotion = w[0] * search.motion(1) + w[1] * search.motion(2) + w[2] * search.motion(3);
        outHit.normal = contactNormal(x0 - q, (x2 - x1).cross(x3 - x1), search.start(0) - q0,
                                      search.motion(0) - qMotion, noise);
    } else {
        const std::array<double, 2> su = closestSegmentParameters(x0, x1, x2, x3);
        outHit.weights = {su[0], su[1], 0.0};
        const double s = su[0], u = su[1];
        const Vec3 pa = x0 + s * (x1 - x0), pc = x2 + u * (x3 - x2);
        const Vec3 startOffset = (search.start(0) + s * (search.start(1) - search.start(0))) -
                                 (search.start(2) + u * (search.start(3) - search.start(2)));
        const Vec3 motion = (search.motion(0) + s * (search.motion(1) - search.motion(0))) -
                            (search.motion(2) + u * (search.motion(3) - search.motion(2)));
        Vec3 cross = (x1 - x0).cross(x3 - x2);
        if (cross.norm() <= noise * noise) {
            // Parallel edges: the separating direction is the start offset's part across edge ab.
            const Vec3 e = x1 - x0;
            const double len2 = e.squaredNorm();
            cross = len2 > 0.0 ? Vec3(startOffset - e * (startOffset.dot(e) / len2)) : startOffset;
        }
        outHit.normal = contactNormal(pa - pc, cross, startOffset, motion, noise);
    }
}

CcdOutcome runCcd(Pair pair, const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                  const CcdSettings& settings, CcdHit& outHit) {
    outHit = CcdHit{};
    if (!allFinite(start, end)) return CcdOutcome::NonFinite;
    const InclusionSearch search(pair, start, end);
    SearchLimits limits;
    limits.eta = settings.thickness + search.roundoff();
    limits.certain = settings.thickness - search.roundoff();
    limits.tolerance = std::max(settings.distanceTolerance, 4.0 * search.roundoff());
    limits.timeTolerance = settings.timeTolerance;
    limits.vertexTriangle = pair == Pair::VertexTriangle;
    double witness = 2.0;  // no certain contact yet

    SearchBox root{0.0, 1.0, 0.0, 1.0, 0.0, 1.0};
    int axis = 0;
    outHit.boxesChecked = 1;
    BoxVerdict verdict = classify(search, root, limits, witness, axis);
    if (verdict == BoxVerdict::Excluded) return CcdOutcome::Separated;
    if (verdict == BoxVerdict::Resolved) {
        fillHit(pair, search, 0.0, outHit);
        return CcdOutcome::Contact;
    }
    // The earliest box first: a binary heap (as std::priority_queue's) on storage this thread
    // keeps, so that the CCD of every garment of every frame does not allocate.
    // Reserved once, deeper than a garment's searches go (measured: 116 boxes queued at most in a
    // walking crowd with self-collision, 4,278 in the self-collision suite's adversarial pairs), so
    // a deeper search in a steady run than in its warm-up does not allocate.
    constexpr std::size_t kReservedBoxes = 1024;
    thread_local std::vector<SearchBox> heap;
    if (heap.capacity() < kReservedBoxes) heap.reserve(kReservedBoxes);
    heap.clear();
    const LaterBox later;
    auto push = [&](const SearchBox& box) {
        heap.push_back(box);
        std::push_heap(heap.begin(), heap.end(), later);
    };
    auto pushHalves = [&push](const SearchBox& box, int splitAxis) {
        SearchBox lower = box, upper = box;
        if (splitAxis == 0) {
            lower.t1 = upper.t0 = 0.5 * (box.t0 + box.t1);
        } else if (splitAxis == 1) {
            lower.u1 = upper.u0 = 0.5 * (box.u0 + box.u1);
        } else {
            lower.v1 = upper.v0 = 0.5 * (box.v0 + box.v1);
        }
        push(lower);
        push(upper);
    };
    pushHalves(root, axis);
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const SearchBox box = heap.back();
        heap.pop_back();
        if (box.t0 >= witness) {
            // Everything before this box was discarded and contact at `witness` is certain.
            fillHit(pair, search, witness, outHit);
            return CcdOutcome::Contact;
        }
        // Barycentric (u, v) beyond the triangle's hypotenuse: outside the face.
        if (pair == Pair::VertexTriangle && box.u0 + box.v0 > 1.0) continue;
        if (outHit.boxesChecked >= settings.maxBoxes) {
            // Every earlier box was excluded, so this box's start is still a safe lower bound.
            outHit.capped = true;
            fillHit(pair, search, box.t0, outHit);
            return CcdOutcome::Contact;
        }
        ++outHit.boxesChecked;
        verdict = classify(search, box, limits, witness, axis);
        if (verdict == BoxVerdict::Excluded) continue;
        if (verdict == BoxVerdict::Resolved) {
            fillHit(pair, search, box.t0, outHit);
            return CcdOutcome::Contact;
        }
        pushHalves(box, axis);
    }
    return CcdOutcome::Separated;
}

} // namespace

CcdOutcome vertexTriangleCcd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                             const CcdSettings& settings, CcdHit& outHit) {
    return runCcd(Pair::VertexTriangle, start, end, settings, outHit);
}

CcdOutcome edgeEdgeCcd(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end,
                       const CcdSettings& settings, CcdHit& outHit) {
    return runCcd(Pair::EdgeEdge, start, end, settings, outHit);
}

} // namespace cc::collision
