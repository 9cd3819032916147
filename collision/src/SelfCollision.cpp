#include "crowdcloth/collision/SelfCollision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cc::collision {

namespace {

/// Pairs closer than this at the start of the step already touch: no normal or side can be told,
/// so they are left alone (x0 is assumed free of contact).
constexpr double kTouching = 1e-12;  // [m]

/// A pair gets separating planes only when its line of closest points is within about 60 degrees
/// of the face's normal.
constexpr double kFaceCone = 0.5;

/// Cosine of the cone within which a vertex's separating planes count as one (about 11 degrees),
/// and how many directions a vertex keeps.
constexpr double kMergeCone = 0.98;
constexpr int kPlanesPerVertex = 4;
// A cache serves while at most this share of the vertices left their cached boxes (their pairs are
// searched one by one); more, and one search of all is cheaper.
constexpr uint32_t kMaxEscapedShare = 4;  // 1 / 4

bool hasVertex(const std::array<uint32_t, 3>& triangle, uint32_t v) {
    return triangle[0] == v || triangle[1] == v || triangle[2] == v;
}

bool shareVertex(const std::array<uint32_t, 2>& a, const std::array<uint32_t, 2>& b) {
    return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

std::string vertexName(std::size_t v) { return "vertex " + std::to_string(v); }

} // namespace

Status SelfCollisionSettings::validate() const {
    if (!(thickness > 0.0) || !std::isfinite(thickness)) {
        return Status::invalidArgument("SelfCollisionSettings.thickness must be finite and > 0, got " +
                                       std::to_string(thickness));
    }
    if (!(repulsionFraction >= 0.0 && repulsionFraction <= 1.0)) {
        return Status::invalidArgument("SelfCollisionSettings.repulsionFraction must be in [0, 1], got " +
                                       std::to_string(repulsionFraction));
    }
    if (!(ccdGap > 0.0 && ccdGap <= thickness)) {
        return Status::invalidArgument("SelfCollisionSettings.ccdGap must be in (0, thickness], got " +
                                       std::to_string(ccdGap));
    }
    if (impulseIterations < 1) {
        return Status::invalidArgument("SelfCollisionSettings.impulseIterations must be >= 1, got " +
                                       std::to_string(impulseIterations));
    }
    if (zoneIterations < 1) {
        return Status::invalidArgument("SelfCollisionSettings.zoneIterations must be >= 1, got " +
                                       std::to_string(zoneIterations));
    }
    if (maxPairsPerTriangle < 1) {
        return Status::invalidArgument("SelfCollisionSettings.maxPairsPerTriangle must be >= 1, got " +
                                       std::to_string(maxPairsPerTriangle));
    }
    return Status::ok();
}

Status SeparatingPlaneSettings::validate() const {
    if (!(thickness > 0.0) || !std::isfinite(thickness))
        return Status::invalidArgument("SeparatingPlaneSettings.thickness must be finite and > 0, got " +
                                       std::to_string(thickness));
    if (!(repulsionFraction >= 0.0 && repulsionFraction <= 1.0))
        return Status::invalidArgument("SeparatingPlaneSettings.repulsionFraction must be in [0, 1], got " +
                                       std::to_string(repulsionFraction));
    if (!(lookahead >= 0.0) || !std::isfinite(lookahead))
        return Status::invalidArgument("SeparatingPlaneSettings.lookahead must be finite and >= 0, got " +
                                       std::to_string(lookahead));
    if (!(maxReach > 0.0) || !std::isfinite(maxReach))
        return Status::invalidArgument("SeparatingPlaneSettings.maxReach must be finite and > 0, got " +
                                       std::to_string(maxReach));
    if (!(acceleration >= 0.0) || !std::isfinite(acceleration))
        return Status::invalidArgument("SeparatingPlaneSettings.acceleration must be finite and >= 0, got " +
                                       std::to_string(acceleration));
    if (!(solverOffset >= 0.0) || !std::isfinite(solverOffset))
        return Status::invalidArgument("SeparatingPlaneSettings.solverOffset must be finite and >= 0, got " +
                                       std::to_string(solverOffset));
    return Status::ok();
}

Result<SelfCollision> SelfCollision::create(Span<const std::array<uint32_t, 3>> triangles, uint32_t vertexCount,
                                            const SelfCollisionSettings& settings) {
    Status valid = settings.validate();
    if (!valid.isOk()) return valid;
    SelfCollision self;
    self.mSettings = settings;
    self.mVertexCount = vertexCount;
    self.mTriangles.assign(triangles.begin(), triangles.end());
    std::vector<std::array<uint32_t, 3>> halfEdges;  // (a, b, triangle * 3 + slot) with a < b
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[k] >= vertexCount) {
                return Status::invalidArgument("SelfCollision: triangle " + std::to_string(t) + " references " +
                                               vertexName(tri[k]) + " of " + std::to_string(vertexCount));
            }
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            return Status::invalidArgument("SelfCollision: triangle " + std::to_string(t) + " repeats a vertex");
        }
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            halfEdges.push_back({std::min(a, b), std::max(a, b), static_cast<uint32_t>(t * 3 + k)});
        }
    }
    std::sort(halfEdges.begin(), halfEdges.end());
    self.mOwned.assign(triangles.size(), {});
    for (const auto& h : halfEdges) {
        if (self.mEdges.empty() || self.mEdges.back()[0] != h[0] || self.mEdges.back()[1] != h[1]) {
            self.mEdges.push_back({h[0], h[1]});
        }
        if (self.mEdgeTriangle.size() < self.mEdges.size()) {
            self.mEdgeTriangle.push_back(h[2] / 3);
            Owned& owner = self.mOwned[h[2] / 3];
            owner.edges[owner.edgeCount++] = static_cast<uint32_t>(self.mEdges.size() - 1);
        }
    }
    // Each vertex's owner: the first triangle that holds it.
    std::vector<uint8_t> owned(vertexCount, 0);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            if (!owned[triangles[t][k]]) {
                owned[triangles[t][k]] = 1;
                self.mOwned[t].vertices[self.mOwned[t].vertexCount++] = triangles[t][k];
            }
    for (uint32_t v = 0; v < vertexCount; ++v)
        if (!owned[v]) self.mLoneVertices.push_back(v);
    // Collision lists sized up front (one per triangle), so a frame with more crossings than the
    // warm-up had does not allocate.
    self.mFound.reserve(triangles.size());
    self.mCollisions.reserve(triangles.size());
    return self;
}

void SelfCollision::sweptBoxes(Span<const Vec3> x0, Span<const Vec3> x1) {
    mVertexBoxes.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        Aabb box;
        box.grow(x0[v]);
        box.grow(x1[v]);
        mVertexBoxes[v] = box;
    }
}

bool SelfCollision::candidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                               std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                               std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    sweptBoxes(x0, x1);
    return candidatesOfBoxes(mVertexBoxes, margin, outVertexTriangle, outEdgeEdge);
}

void SelfCollision::hullBoxes(Span<const Aabb> vertexBoxes, double margin) {
    auto hull = [&](const auto& vertices) {
        Aabb box;
        for (uint32_t v : vertices) {
            box.grow(vertexBoxes[v].lo);
            box.grow(vertexBoxes[v].hi);
        }
        return box;
    };
    // The tree's boxes are grown by half the margin, so two overlap when their triangles' hulls
    // come within the margin, which is all a primitive pair of theirs needs (a primitive's box is
    // in its owner's hull): growing both by the whole margin let in twice the gap, and 12 % more
    // triangle pairs in the self-collision study, for nothing. The hair over half keeps rounding
    // from losing a pair.
    mTreeMargin = 0.5 * margin * (1.0 + 1e-6);
    mBoxes.resize(mTriangles.size());
    mTreeBoxes.resize(mTriangles.size());
    for (std::size_t t = 0; t < mTriangles.size(); ++t) {
        mBoxes[t] = hull(mTriangles[t]);
        mTreeBoxes[t] = mBoxes[t];
        mTreeBoxes[t].inflate(mTreeMargin);
        mBoxes[t].inflate(margin);
    }
    mEdgeBoxes.resize(mEdges.size());
    mGrownEdgeBoxes.resize(mEdges.size());
    for (std::size_t e = 0; e < mEdges.size(); ++e) {
        mEdgeBoxes[e] = hull(mEdges[e]);
        mGrownEdgeBoxes[e] = mEdgeBoxes[e];
        mGrownEdgeBoxes[e].inflate(margin);
    }
}

Aabb SelfCollision::treeQuery(const Aabb& box) const {
    Aabb query = box;
    query.inflate(2.0 * mTreeMargin);  // a little over the margin: every box mBoxes would meet
    return query;
}

bool SelfCollision::edgesOverlap(uint32_t e, uint32_t f) const {
    return mGrownEdgeBoxes[std::max(e, f)].overlaps(mEdgeBoxes[std::min(e, f)]);
}

void SelfCollision::fitTree() {
    if (mBvhBuilt) {
        mBvh.refit(mTreeBoxes);
    } else {
        mBvh.build(mTreeBoxes);
        mBvhBuilt = true;
    }
}

std::size_t SelfCollision::maxTrianglePairs() const {
    return std::size_t(mSettings.maxPairsPerTriangle) * mTriangles.size();
}

bool SelfCollision::candidatesOfBoxes(Span<const Aabb> vertexBoxes, double margin,
                                      std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                      std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    outVertexTriangle.clear();
    outEdgeEdge.clear();
    // Triangle boxes (the hull of their vertices' boxes) grown by the margin; a vertex or edge box
    // overlaps one whenever their L-infinity gap, hence their distance, can be below the margin.
    hullBoxes(vertexBoxes, margin);
    fitTree();
    // Every vertex and edge is owned by one triangle holding it, whose box holds its box: a pair
    // that overlaps is found through its owners' pair, once (adjacent primitives share a triangle
    // or a vertex and are skipped). Vertices of no triangle ask the tree themselves.
    mTrianglePairs.clear();
    // A crumpled garment (a coarse level's fold prolonged to a fine one) meets tens of times the
    // pairs of any cloth surface: past the cap it is left to itself, at a bounded cost.
    mCrowded = !mBvh.overlappingPairs(mTrianglePairs, maxTrianglePairs());
    if (mCrowded) return false;
    pairsOfTrianglePairs(vertexBoxes, false, outVertexTriangle, outEdgeEdge);
    std::vector<uint32_t>& hits = mHits;
    for (uint32_t v : mLoneVertices) {
        hits.clear();
        mBvh.query(treeQuery(vertexBoxes[v]), hits);
        for (uint32_t t : hits)  // a lone vertex is in no triangle
            if (mBoxes[t].overlaps(vertexBoxes[v])) outVertexTriangle.push_back({v, t});
    }
    // Sorted (each pair is found once): results do not depend on the tree's order.
    sortCandidates(outVertexTriangle, outEdgeEdge);
    return true;
}

void SelfCollision::pairsOfTrianglePairs(Span<const Aabb> vertexBoxes, bool markedOnly,
                                         std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                         std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    auto vertexTriangle = [&](uint32_t v, uint32_t t) {
        if ((!markedOnly || mMarked[v] || mMarkedTriangle[t]) && !hasVertex(mTriangles[t], v) &&
            mBoxes[t].overlaps(vertexBoxes[v]))
            outVertexTriangle.push_back({v, t});
    };
    for (const auto& [t, u] : mTrianglePairs) {
        const Owned& a = mOwned[t];
        const Owned& b = mOwned[u];
        for (uint32_t k = 0; k < a.vertexCount; ++k) vertexTriangle(a.vertices[k], u);
        for (uint32_t k = 0; k < b.vertexCount; ++k) vertexTriangle(b.vertices[k], t);
        for (uint32_t k = 0; k < a.edgeCount; ++k)
            for (uint32_t j = 0; j < b.edgeCount; ++j) {
                const uint32_t e = a.edges[k], f = b.edges[j];
                if ((!markedOnly || markedEdge(e) || markedEdge(f)) && !shareVertex(mEdges[e], mEdges[f]) &&
                    edgesOverlap(e, f))
                    outEdgeEdge.push_back({std::min(e, f), std::max(e, f)});
            }
    }
}

void SelfCollision::sortPairs(std::vector<std::array<uint32_t, 2>>& pairs, uint32_t firstCount,
                              uint32_t secondCount) {
    // Two stable counting sorts, by the second index and then by the first (an LSD radix sort):
    // linear, where a general sort of tens of thousands of pairs cost more than the search that
    // found them, and where sorting each first index's bucket by insertion took a tenth of the
    // garment's self-collision (a vertex meets its triangles in the tree's order, not theirs).
    mSortedPairs.resize(pairs.size());
    auto byIndex = [&](int which, uint32_t count, const std::vector<std::array<uint32_t, 2>>& from,
                       std::vector<std::array<uint32_t, 2>>& to) {
        mBucketStart.assign(std::size_t(count) + 1, 0);
        for (const auto& p : from) ++mBucketStart[p[which] + 1];
        for (uint32_t i = 0; i < count; ++i) mBucketStart[i + 1] += mBucketStart[i];
        for (const auto& p : from) to[mBucketStart[p[which]]++] = p;
    };
    byIndex(1, secondCount, pairs, mSortedPairs);
    byIndex(0, firstCount, mSortedPairs, pairs);
}

bool SelfCollision::pairsFromCache(const PairCache& cache, Span<const Aabb> vertexBoxes, double margin,
                                   std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                   std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    if (!cache.valid || margin > cache.margin || cache.boxes.size() != mVertexCount) return false;
    mMarked.assign(mVertexCount, 0);  // escaped from its cached box
    uint32_t escaped = 0;
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        const Aabb& kept = cache.boxes[v];
        if ((vertexBoxes[v].lo.array() >= kept.lo.array()).all() && (vertexBoxes[v].hi.array() <= kept.hi.array()).all())
            continue;
        mMarked[v] = 1;
        ++escaped;
    }
    if (escaped > mVertexCount / kMaxEscapedShare) return false;
    hullBoxes(vertexBoxes, margin);
    markTriangles();
    outVertexTriangle.clear();
    outEdgeEdge.clear();
    // Pairs whose vertices all stayed in their cached boxes: every one that overlaps now overlapped
    // there (a larger or equal margin), so it is in the cache; the same test as candidatesOfBoxes.
    for (const auto& pair : cache.vf)
        if (!mMarked[pair[0]] && !mMarkedTriangle[pair[1]] && mBoxes[pair[1]].overlaps(vertexBoxes[pair[0]]))
            outVertexTriangle.push_back(pair);
    for (const auto& pair : cache.ee)
        if (!markedEdge(pair[0]) && !markedEdge(pair[1]) && edgesOverlap(pair[0], pair[1]))
            outEdgeEdge.push_back(pair);
    if (escaped == 0) return true;  // sorted, as the cache's lists are
    // Pairs with an escaped vertex, searched.
    if (!appendMarkedPairs(vertexBoxes, outVertexTriangle, outEdgeEdge)) {
        outVertexTriangle.clear();
        outEdgeEdge.clear();
        return false;
    }
    sortCandidates(outVertexTriangle, outEdgeEdge);
    return true;
}

void SelfCollision::sortCandidates(std::vector<std::array<uint32_t, 2>>& vertexTriangle,
                                   std::vector<std::array<uint32_t, 2>>& edgeEdge) {
    sortPairs(vertexTriangle, mVertexCount, uint32_t(mTriangles.size()));
    sortPairs(edgeEdge, uint32_t(mEdges.size()), uint32_t(mEdges.size()));
}

bool SelfCollision::markedEdge(uint32_t e) const { return mMarked[mEdges[e][0]] || mMarked[mEdges[e][1]]; }

void SelfCollision::markTriangles() {
    mMarkedTriangle.resize(mTriangles.size());
    for (uint32_t t = 0; t < mTriangles.size(); ++t) {
        const auto& tri = mTriangles[t];
        mMarkedTriangle[t] = mMarked[tri[0]] || mMarked[tri[1]] || mMarked[tri[2]];
    }
}

bool SelfCollision::appendMarkedPairs(Span<const Aabb> vertexBoxes,
                                      std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                      std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    // One descent of the tree (refit to the current boxes) through the marked triangles: every
    // vertex and edge is met through its owner, which holds it, so a pair with a marked vertex
    // comes from a triangle pair with a marked triangle in it.
    fitTree();
    mTrianglePairs.clear();
    mCrowded = !mBvh.overlappingPairs(mMarkedTriangle, mTrianglePairs, maxTrianglePairs());
    if (mCrowded) return false;
    pairsOfTrianglePairs(vertexBoxes, true, outVertexTriangle, outEdgeEdge);
    std::vector<uint32_t>& hits = mHits;
    for (uint32_t v : mLoneVertices) {  // vertices of no triangle have no owner
        if (mMarked[v]) {
            hits.clear();
            mBvh.query(treeQuery(vertexBoxes[v]), hits);
            for (uint32_t t : hits)
                if (mBoxes[t].overlaps(vertexBoxes[v])) outVertexTriangle.push_back({v, t});
        } else {
            for (uint32_t t = 0; t < mTriangles.size(); ++t)
                if (mMarkedTriangle[t] && mBoxes[t].overlaps(vertexBoxes[v])) outVertexTriangle.push_back({v, t});
        }
    }
    return true;
}

bool SelfCollision::changedCandidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                                      std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                      std::vector<std::array<uint32_t, 2>>& outEdgeEdge) {
    sweptBoxes(x0, x1);
    mMarked.assign(mChanged.begin(), mChanged.end());
    markTriangles();
    hullBoxes(mVertexBoxes, margin);
    outVertexTriangle.clear();
    outEdgeEdge.clear();
    if (!appendMarkedPairs(mVertexBoxes, outVertexTriangle, outEdgeEdge)) return false;
    sortCandidates(outVertexTriangle, outEdgeEdge);
    return true;
}

bool SelfCollision::sweptCandidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                                    std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                                    std::vector<std::array<uint32_t, 2>>& outEdgeEdge, SelfCollisionStats& stats) {
    sweptBoxes(x0, x1);
    const bool sameStart =
        mUpdate.valid && x0.size() == mUpdateStart.size() && std::equal(x0.begin(), x0.end(), mUpdateStart.begin());
    if (sameStart && pairsFromCache(mUpdate, mVertexBoxes, margin, outVertexTriangle, outEdgeEdge)) return true;
    ++stats.broadPhases;
    return candidatesOfBoxes(mVertexBoxes, margin, outVertexTriangle, outEdgeEdge);
}

namespace {

/// A pair as signed weights on its 4 vertices: separation = sum w_i x_i points from the triangle
/// (edge cd) to the vertex (edge ab).
struct PairGeometry {
    std::array<uint32_t, 4> vertices;
    std::array<double, 4> weights;
};

PairGeometry vertexTrianglePair(uint32_t v, const std::array<uint32_t, 3>& tri, const std::array<double, 3>& w) {
    return {{v, tri[0], tri[1], tri[2]}, {1.0, -w[0], -w[1], -w[2]}};
}

PairGeometry edgeEdgePair(const std::array<uint32_t, 2>& a, const std::array<uint32_t, 2>& b, double s, double u) {
    return {{a[0], a[1], b[0], b[1]}, {1.0 - s, s, -(1.0 - u), -u}};
}

/// Unit normal of a triangle at x (zero for a degenerate one, which then faces nothing).
Vec3 unitNormal(Span<const Vec3> x, const std::array<uint32_t, 3>& tri) {
    const Vec3 n = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
    const double length = n.norm();
    return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

Vec3 separation(const PairGeometry& g, Span<const Vec3> x) {
    Vec3 d = Vec3::Zero();
    for (int i = 0; i < 4; ++i) d += g.weights[i] * x[g.vertices[i]];
    return d;
}

} // namespace

Status SelfCollision::separatingPlanes(Span<const Vec3> x0, Span<const Vec3> velocities, double dt,
                                       const SeparatingPlaneSettings& settings, std::vector<Contact>& outPlanes) {
    if (Status valid = settings.validate(); !valid) return valid;
    if (!(dt > 0.0) || !std::isfinite(dt))
        return Status::invalidArgument("SelfCollision::separatingPlanes: dt must be finite and > 0, got " +
                                       std::to_string(dt));
    if (x0.size() != mVertexCount || velocities.size() != mVertexCount)
        return Status::invalidArgument("SelfCollision::separatingPlanes: expected " + std::to_string(mVertexCount) +
                                       " positions and velocities, got " + std::to_string(x0.size()) + " and " +
                                       std::to_string(velocities.size()));
    // Where each vertex could get to: its velocity over `lookahead` steps, at most maxReach.
    mReachEnd.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        if (!isFinite(x0[v]) || !isFinite(velocities[v]))
            return Status::invalidArgument("SelfCollision::separatingPlanes: non-finite position or velocity at " +
                                           vertexName(v));
        Vec3 motion = (settings.lookahead * dt) * velocities[v];
        const double length = motion.norm();
        if (length > settings.maxReach) motion *= settings.maxReach / length;
        mReachEnd[v] = x0[v] + motion;
    }
    const double h = settings.thickness;
    // A layer held by the body under one that falls onto it closes at the acceleration the other
    // feels, which a velocity does not show yet.
    const double accelerationReach = 0.5 * settings.acceleration * (settings.lookahead * dt) * (settings.lookahead * dt);
    // The update's broad phase: each vertex's box reaches as far as its look-ahead and the
    // acceleration could carry it; resolve() filters these pairs after the solve (sweptCandidates).
    mUpdate.boxes.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        Aabb box;
        box.grow(x0[v]);
        box.grow(mReachEnd[v]);
        box.inflate(accelerationReach);
        mUpdate.boxes[v] = box;
    }
    mUpdate.valid = false;
    if (!candidatesOfBoxes(mUpdate.boxes, h, mUpdate.vf, mUpdate.ee)) return Status::ok();  // crumpled: no planes
    mUpdate.margin = h;
    mUpdate.valid = true;
    mUpdateStart.assign(x0.begin(), x0.end());

    // Layers at rest give a vertex a plane from every primitive of the other layer within reach,
    // all facing nearly the same way: planes within kMergeCone of one another are one plane, the
    // one that reaches farthest along its normal at the step's end (the solver projects each plane
    // in turn, so near-copies cost time and settle nothing). A vertex keeps kPlanesPerVertex
    // directions; a further one merges into the nearest. Pairs come in sorted order, so which plane
    // is kept does not depend on threads.
    mPlanes.resize(std::size_t(mVertexCount) * kPlanesPerVertex);
    mPlaneCount.assign(mVertexCount, 0);
    auto keepPlane = [&](const Contact& c) {
        Contact* slots = &mPlanes[std::size_t(c.vertex) * kPlanesPerVertex];
        uint8_t& count = mPlaneCount[c.vertex];
        int nearest = -1;
        double nearestCos = -2.0;
        for (int k = 0; k < count; ++k) {
            const double cosine = slots[k].normal.dot(c.normal);
            if (cosine > nearestCos) nearestCos = cosine, nearest = k;
        }
        if (nearestCos < kMergeCone && count < kPlanesPerVertex) {
            slots[count++] = c;
        } else if (slots[nearest].normal.dot(c.point - slots[nearest].point) > 0.0) {
            slots[nearest] = c;
        }
    };
    uint32_t ordinal = 0;
    // sideA: how many of the pair's vertices are on the side the separation points to.
    auto addPair = [&](const PairGeometry& g, int sideA, const Vec3& faceNormal) {
        const uint32_t pair = ordinal++;
        const Vec3 d = separation(g, x0);
        const double gap = d.norm();
        if (gap <= kTouching) return;
        const Vec3 n = d / gap;
        // The pair's approach along its normal over the look-ahead (negative = closing): a pair
        // that moves together, neighbours in a falling sheet, needs no plane however close.
        double opening = 0.0;
        Vec3 pointA = Vec3::Zero(), pointB = Vec3::Zero(), velocityA = Vec3::Zero(), velocityB = Vec3::Zero();
        for (int i = 0; i < 4; ++i) {
            const uint32_t v = g.vertices[i];
            opening += g.weights[i] * (mReachEnd[v] - x0[v]).dot(n);
            (i < sideA ? pointA : pointB) += std::abs(g.weights[i]) * x0[v];
            (i < sideA ? velocityA : velocityB) += std::abs(g.weights[i]) * velocities[v];
        }
        if (gap >= h + std::max(0.0, -opening) + accelerationReach) return;
        // Layers meet face to face: a pair whose line of closest points lies along the cloth
        // (neighbours a few rings apart in a sheet, whose only way to meet is to squash the cloth
        // between them) gets no plane; the continuous tests after the solve still watch it.
        if (std::abs(n.dot(faceNormal)) < kFaceCone) return;
        const double kept = gap >= h ? h : gap + settings.repulsionFraction * (h - gap);
        const Vec3 velocity = 0.5 * (velocityA + velocityB);
        const Vec3 midAtEnd = 0.5 * (pointA + pointB) + dt * velocity;
        for (int i = 0; i < 4; ++i) {
            const Vec3 normal = i < sideA ? n : Vec3(-n);
            Contact c;
            c.vertex = g.vertices[i];
            c.primitive = pair;
            c.normal = normal;
            c.point = midAtEnd + (0.5 * kept - settings.solverOffset) * normal;
            c.surfaceVelocity = velocity;
            c.depth = 0.5 * kept - normal.dot(x0[c.vertex] - 0.5 * (pointA + pointB));
            keepPlane(c);
        }
    };
    // Each triangle's normal once (a pair asks for one or two of them, and tens of pairs share a
    // triangle).
    mNormals.resize(mTriangles.size());
    for (std::size_t t = 0; t < mTriangles.size(); ++t) mNormals[t] = unitNormal(x0, mTriangles[t]);
    for (const auto& pair : mUpdate.vf) {
        const auto& tri = mTriangles[pair[1]];
        const std::array<double, 3> w = closestTriangleWeights(x0[pair[0]], x0[tri[0]], x0[tri[1]], x0[tri[2]]);
        addPair(vertexTrianglePair(pair[0], tri, w), 1, mNormals[pair[1]]);
    }
    for (const auto& pair : mUpdate.ee) {
        const auto& a = mEdges[pair[0]];
        const auto& b = mEdges[pair[1]];
        // Closest at an end of either edge: that end's vertex-triangle pairs hold the same plane.
        std::array<double, 2> su{};
        if (!interiorClosestSegmentParameters(x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], su)) continue;
        // The face of either edge's first triangle that is more nearly across the pair.
        const Vec3& na = mNormals[mEdgeTriangle[pair[0]]];
        const Vec3& nb = mNormals[mEdgeTriangle[pair[1]]];
        const Vec3 d = (1.0 - su[0]) * x0[a[0]] + su[0] * x0[a[1]] - (1.0 - su[1]) * x0[b[0]] - su[1] * x0[b[1]];
        addPair(edgeEdgePair(a, b, su[0], su[1]), 2, std::abs(d.dot(na)) >= std::abs(d.dot(nb)) ? na : nb);
    }
    for (uint32_t v = 0; v < mVertexCount; ++v)
        for (uint32_t k = 0; k < mPlaneCount[v]; ++k) outPlanes.push_back(mPlanes[std::size_t(v) * kPlanesPerVertex + k]);
    return Status::ok();
}

void SelfCollision::applyImpulse(const Collision& c, Span<const Vec3> x0, Span<Vec3> x1) const {
    double approach = 0.0, denominator = 0.0;
    for (int i = 0; i < 4; ++i) {
        approach += c.weights[i] * (x1[c.vertices[i]] - x0[c.vertices[i]]).dot(c.normal);
        denominator += c.weights[i] * c.weights[i] * mInvMass[c.vertices[i]];
    }
    // Inelastic: cancel the relative normal motion of an approaching pair (Bridson et al. 2002, 7.1),
    // shared by inverse mass so that pinned vertices keep their motion.
    if (approach >= 0.0 || denominator <= 0.0) return;
    const double lambda = -approach / denominator;
    for (int i = 0; i < 4; ++i) {
        x1[c.vertices[i]] += (lambda * c.weights[i] * mInvMass[c.vertices[i]]) * c.normal;
    }
}

void SelfCollision::applyProximity(Span<const Vec3> x0, Span<Vec3> x1, SelfCollisionStats& stats) {
    std::vector<std::array<uint32_t, 2>>& vf = mPairsVf;
    std::vector<std::array<uint32_t, 2>>& ee = mPairsEe;
    const double h = mSettings.thickness;
    if (!candidates(x0, x0, h, vf, ee)) {
        stats.crowded = 1;
        return;
    }
    // Repulsion from the start-of-step geometry, whose side of each pair is trusted: the pair's
    // relative normal motion over the step must recover `repulsionFraction` of the overlap
    // (Bridson et al. 2002, 7.2, in position form), which also stops approaching pairs.
    auto respond = [&](const PairGeometry& g) {
        const Vec3 d = separation(g, x0);
        const double gap = d.norm();
        if (gap >= h || gap <= kTouching) return;
        ++stats.proximityPairs;
        const Vec3 n = d / gap;
        double motion = 0.0, denominator = 0.0;
        for (int i = 0; i < 4; ++i) {
            motion += g.weights[i] * (x1[g.vertices[i]] - x0[g.vertices[i]]).dot(n);
            denominator += g.weights[i] * g.weights[i] * mInvMass[g.vertices[i]];
        }
        const double target = mSettings.repulsionFraction * (h - gap);
        if (motion >= target || denominator <= 0.0) return;
        ++stats.repulsions;
        const double lambda = (target - motion) / denominator;
        for (int i = 0; i < 4; ++i) x1[g.vertices[i]] += (lambda * g.weights[i] * mInvMass[g.vertices[i]]) * n;
    };
    for (const auto& pair : vf) {
        const auto& tri = mTriangles[pair[1]];
        const std::array<double, 3> w = closestTriangleWeights(x0[pair[0]], x0[tri[0]], x0[tri[1]], x0[tri[2]]);
        respond(vertexTrianglePair(pair[0], tri, w));
    }
    for (const auto& pair : ee) {
        const auto& a = mEdges[pair[0]];
        const auto& b = mEdges[pair[1]];
        const std::array<double, 2> su = closestSegmentParameters(x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]]);
        respond(edgeEdgePair(a, b, su[0], su[1]));
    }
}

bool SelfCollision::findCollisions(Span<const Vec3> x0, Span<const Vec3> x1, std::vector<Collision>& outCollisions,
                                   SelfCollisionStats& stats) {
    std::vector<std::array<uint32_t, 2>>& vf = mPairsVf;
    std::vector<std::array<uint32_t, 2>>& ee = mPairsEe;
    // A pass after the first re-tests only pairs with a vertex the last pass's impulses or zones
    // moved, or one in a collision then: a test depends on its four vertices' x0 and x1 alone, so
    // any other pair tested clear last time is clear now. So the pass searches for candidates only
    // through the triangles holding such a vertex, and tests those. The fail-safe's dozens of
    // passes cost little more than the first.
    mChanged.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        mChanged[v] = !mRetestMovedOnly || mInLastCollision[v] || !(x1[v] == mLastEnd[v]);
        mInLastCollision[v] = 0;
    }
    outCollisions.clear();
    const bool searched = mRetestMovedOnly ? changedCandidates(x0, x1, mSettings.ccdGap, vf, ee)
                                           : sweptCandidates(x0, x1, mSettings.ccdGap, vf, ee, stats);
    if (!searched) return false;
    const std::size_t total = vf.size() + ee.size();
    mLastEnd.assign(x1.begin(), x1.end());
    mRetestMovedOnly = true;
    std::vector<Collision>& found = mFound;
    std::vector<uint8_t>& status = mStatus;  // 0 none, 1 contact, 2 contact with capped search
    std::vector<uint32_t>& boxes = mBoxCounts;
    found.resize(total);
    status.assign(total, 0);
    boxes.assign(total, 0);
    parallelFor(static_cast<int64_t>(total), mSettings.parallel, [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k) {
            const bool isVf = static_cast<std::size_t>(k) < vf.size();
            std::array<uint32_t, 4> ids;
            if (isVf) {
                const auto& pair = vf[k];
                const auto& tri = mTriangles[pair[1]];
                ids = {pair[0], tri[0], tri[1], tri[2]};
            } else {
                const auto& pair = ee[k - vf.size()];
                ids = {mEdges[pair[0]][0], mEdges[pair[0]][1], mEdges[pair[1]][0], mEdges[pair[1]][1]};
            }
            bool moving = false, changed = false;
            for (uint32_t v : ids) moving = moving || x1[v] != x0[v], changed = changed || mChanged[v];
            if (!moving || !changed) continue;  // a pair that does not move cannot start to cross
            std::array<Vec3, 4> start, finish;
            for (int i = 0; i < 4; ++i) {
                start[i] = x0[ids[i]];
                finish[i] = x1[ids[i]];
            }
            // From the closest point of the triangle (edge cd) to the vertex (edge ab).
            auto separationOf = [isVf](const std::array<Vec3, 4>& x) -> Vec3 {
                if (isVf) {
                    const auto w = closestTriangleWeights(x[0], x[1], x[2], x[3]);
                    return x[0] - w[0] * x[1] - w[1] * x[2] - w[2] * x[3];
                }
                const auto su = closestSegmentParameters(x[0], x[1], x[2], x[3]);
                return x[0] + su[0] * (x[1] - x[0]) - x[2] - su[1] * (x[3] - x[2]);
            };
            const Vec3 d0 = separationOf(start);
            const double gap0 = d0.norm();
            if (gap0 <= kTouching) continue;
            // Keep at least a quarter of the start gap: then a rigid motion of the pair (an impact
            // zone) is never reported, since the L-infinity test sees at least gap0 / sqrt(3), and
            // the margin between the two keeps the search short.
            CcdSettings ccd;
            ccd.thickness = std::min(mSettings.ccdGap, 0.25 * gap0);
            ccd.timeTolerance = 1e-5;  // toi only places the normal and weights of the impulse
            // Cheap proofs of separation first. (1) The closest points' relative motion is a convex
            // combination of the vertices' relative motions across the pair, so the distance changes
            // at most by `reach`, the largest of those, over the step and stays above
            // (gap0 + gap1 - reach) / 2. Most candidates of a garment at rest in layers end here, and
            // so do neighbours in a sheet that falls or swings as one (relative, not absolute motion).
            const int sideA = isVf ? 1 : 2;
            const double kept = 1.01 * ccd.thickness;
            double reach = 0.0;
            for (int i = 0; i < sideA; ++i)
                for (int j = sideA; j < 4; ++j)
                    reach = std::max(reach, ((finish[i] - start[i]) - (finish[j] - start[j])).norm());
            const Vec3 d1 = separationOf(finish);
            const double gap1 = d1.norm();
            if (0.5 * (gap0 + gap1 - reach) > kept) continue;
            // (2) A fixed axis along which every vertex of one side stays ahead of every vertex of
            // the other by `kept` at both ends of the step: each such difference is linear in time,
            // so it holds throughout, and so does the distance of any two points of the primitives.
            // Pairs the solve held apart by their separating plane (in contact, moving fast against
            // each other: the first proof fails on them) end here.
            auto apartAlong = [&](const Vec3& axis) {
                for (const std::array<Vec3, 4>* x : {&start, &finish}) {
                    double lowA = std::numeric_limits<double>::infinity();
                    double highB = -lowA;
                    for (int i = 0; i < 4; ++i) {
                        const double along = axis.dot((*x)[i]);
                        if (i < sideA) lowA = std::min(lowA, along);
                        else highB = std::max(highB, along);
                    }
                    if (lowA - highB <= kept) return false;
                }
                return true;
            };
            if (apartAlong(d0 / gap0) || (gap1 > kTouching && apartAlong(d1 / gap1))) continue;
            ccd.distanceTolerance = 0.1 * ccd.thickness;
            CcdHit hit;
            const CcdOutcome outcome =
                isVf ? vertexTriangleCcd(start, finish, ccd, hit) : edgeEdgeCcd(start, finish, ccd, hit);
            boxes[k] = static_cast<uint32_t>(hit.boxesChecked);
            if (outcome != CcdOutcome::Contact) continue;
            Collision& c = found[k];
            c.vertices = ids;
            c.normal = hit.normal;
            if (isVf) {
                c.weights = {1.0, -hit.weights[0], -hit.weights[1], -hit.weights[2]};
            } else {
                const double s = hit.weights[0], u = hit.weights[1];
                c.weights = {1.0 - s, s, -(1.0 - u), -u};
            }
            status[k] = hit.capped ? 2 : 1;
        }
    });
    stats.ccdTests += static_cast<uint32_t>(total);
    outCollisions.clear();
    for (std::size_t k = 0; k < total; ++k) {
        stats.ccdBoxes += boxes[k];
        if (status[k] == 0) continue;
        if (status[k] == 2) ++stats.cappedTests;
        outCollisions.push_back(found[k]);
        for (uint32_t v : found[k].vertices) mInLastCollision[v] = 1;
    }
    return true;
}

void SelfCollision::rigidifyZones(Span<const Vec3> x0, Span<Vec3> x1, const std::vector<Collision>& collisions,
                                  SelfCollisionStats& stats) {
    auto find = [this](uint32_t v) {
        while (mZoneParent[v] != v) {
            mZoneParent[v] = mZoneParent[mZoneParent[v]];
            v = mZoneParent[v];
        }
        return v;
    };
    for (const Collision& c : collisions) {
        for (int i = 0; i < 4; ++i) {
            mInZone[c.vertices[i]] = 1;
            const uint32_t a = find(c.vertices[0]), b = find(c.vertices[i]);
            if (a != b) mZoneParent[std::max(a, b)] = std::min(a, b);  // smallest index is the root
        }
    }
    // Members grouped by root, in vertex order: the zones and their sums do not depend on threads.
    std::vector<std::array<uint32_t, 2>>& members = mZoneMembers;  // (root, vertex)
    members.clear();
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        if (mInZone[v]) members.push_back({find(v), v});
    }
    std::sort(members.begin(), members.end());
    stats.impactZones = 0;
    stats.zoneVertices = static_cast<uint32_t>(members.size());
    for (std::size_t begin = 0; begin < members.size();) {
        std::size_t end = begin;
        while (end < members.size() && members[end][0] == members[begin][0]) ++end;
        ++stats.impactZones;
        // Rigid motion of the zone with its linear and angular momentum over the step (Provot
        // 1997; Bridson et al. 2002, 7.4). Pinned members fix the zone to their own motion.
        Vec3 pinnedMotion = Vec3::Zero();
        int pinned = 0;
        double mass = 0.0;
        Vec3 centre = Vec3::Zero(), motion = Vec3::Zero();
        for (std::size_t k = begin; k < end; ++k) {
            const uint32_t v = members[k][1];
            if (mInvMass[v] == 0.0) {
                pinnedMotion += x1[v] - x0[v];
                ++pinned;
                continue;
            }
            const double m = 1.0 / mInvMass[v];
            mass += m;
            centre += m * x0[v];
            motion += m * (x1[v] - x0[v]);
        }
        if (pinned > 0) {
            // No rigid motion fits pins that move apart; the pins' mean motion is the closest.
            const Vec3 shift = pinnedMotion / pinned;
            for (std::size_t k = begin; k < end; ++k) {
                const uint32_t v = members[k][1];
                if (mInvMass[v] != 0.0) x1[v] = x0[v] + shift;
            }
            begin = end;
            continue;
        }
        centre /= mass;
        motion /= mass;
        Vec3 angular = Vec3::Zero();
        Mat3 inertia = Mat3::Zero();
        for (std::size_t k = begin; k < end; ++k) {
            const uint32_t v = members[k][1];
            const double m = 1.0 / mInvMass[v];
            const Vec3 r = x0[v] - centre;
            angular += m * r.cross(x1[v] - x0[v] - motion);
            inertia += m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
        }
        // Collinear members have a singular inertia: the tiny shift keeps the solve finite and
        // leaves the spin about their common line at zero.
        const double trace = inertia.trace();
        const Mat3 regularised = inertia + (1e-9 * trace + 1e-300) * Mat3::Identity();
        const Vec3 rotation = regularised.inverse() * angular;  // [rad] rotation vector over the step
        const double angle = rotation.norm();
        const Mat3 spin = angle > 0.0 ? Mat3(Eigen::AngleAxisd(angle, rotation / angle)) : Mat3::Identity();
        for (std::size_t k = begin; k < end; ++k) {
            const uint32_t v = members[k][1];
            x1[v] = centre + motion + spin * (x0[v] - centre);
        }
        begin = end;
    }
}

Status SelfCollision::crowdedResolve(SelfCollisionStats& stats) {
    stats.crowded = 1;
    mLastResolveClean = false;
    return Status::ok();
}

Status SelfCollision::resolve(Span<const Vec3> x0, Span<Vec3> x1, Span<const double> masses,
                              SelfCollisionStats& outStats) {
    outStats = SelfCollisionStats{};
    const bool continuesLast = mLastResolveClean && x0.size() == mResolveStart.size() &&
                               std::equal(x0.begin(), x0.end(), mResolveStart.begin());
    mLastResolveClean = false;
    if (x0.size() != mVertexCount || x1.size() != mVertexCount || masses.size() != mVertexCount) {
        return Status::invalidArgument("SelfCollision::resolve: expected " + std::to_string(mVertexCount) +
                                       " positions and masses, got x0 " + std::to_string(x0.size()) + ", x1 " +
                                       std::to_string(x1.size()) + ", masses " + std::to_string(masses.size()));
    }
    mInvMass.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) {
        if (!isFinite(x0[v]) || !isFinite(x1[v])) {
            return Status::invalidArgument("SelfCollision::resolve: non-finite position at " + vertexName(v));
        }
        const double m = masses[v];
        if (!(m >= 0.0)) {
            return Status::invalidArgument("SelfCollision::resolve: mass of " + vertexName(v) +
                                           " must be >= 0 (0 or inf = pinned), got " + std::to_string(m));
        }
        mInvMass[v] = (m == 0.0 || std::isinf(m)) ? 0.0 : 1.0 / m;
    }
    SelfCollisionStats& stats = outStats;
    const Span<const Vec3> x1View(x1.data(), x1.size());
    // The first pass tests every pair, unless this call continues one that ended clear from the
    // same x0 (the fail-safe again after the strain limit moved a few vertices): then every pair
    // whose vertices kept their x1 was tested clear by that call, and only the others are tested.
    mRetestMovedOnly = continuesLast;
    if (!continuesLast) mInLastCollision.assign(mVertexCount, 0);
    mResolveStart.assign(x0.begin(), x0.end());
    if (mSettings.proximityPass) applyProximity(x0, x1, stats);

    std::vector<Collision>& collisions = mCollisions;
    if (!findCollisions(x0, x1View, collisions, stats)) return crowdedResolve(stats);
    stats.firstPassCollisions = static_cast<uint32_t>(collisions.size());
    for (int iteration = 0; iteration < mSettings.impulseIterations && !collisions.empty(); ++iteration) {
        ++stats.impulseIterations;
        for (const Collision& c : collisions) applyImpulse(c, x0, x1);
        if (!findCollisions(x0, x1View, collisions, stats)) return crowdedResolve(stats);
    }
    if (collisions.empty()) {
        mLastResolveClean = true;
        return Status::ok();
    }

    // Fail-safe: rigid impact zones, merged as new collisions appear.
    stats.failSafeActivations = 1;
    mZoneParent.resize(mVertexCount);
    for (uint32_t v = 0; v < mVertexCount; ++v) mZoneParent[v] = v;
    mInZone.assign(mVertexCount, 0);
    for (int iteration = 0; iteration < mSettings.zoneIterations && !collisions.empty(); ++iteration) {
        ++stats.zoneIterations;
        rigidifyZones(x0, x1, collisions, stats);
        if (!findCollisions(x0, x1View, collisions, stats)) return crowdedResolve(stats);
    }
    // Last resort: hold the vertices of what still collides at x0, which was free of intersections.
    std::vector<uint8_t>& stopped = mStopped;
    stopped.assign(mVertexCount, 0);
    while (!collisions.empty()) {
        bool progress = false;
        for (const Collision& c : collisions) {
            for (uint32_t v : c.vertices) {
                if (mInvMass[v] == 0.0 || stopped[v]) continue;
                stopped[v] = 1;
                x1[v] = x0[v];
                ++stats.stoppedVertices;
                progress = true;
            }
        }
        if (!progress) break;
        if (!findCollisions(x0, x1View, collisions, stats)) return crowdedResolve(stats);
    }
    stats.unresolved = static_cast<uint32_t>(collisions.size());
    mLastResolveClean = collisions.empty();
    return Status::ok();
}

} // namespace cc::collision
