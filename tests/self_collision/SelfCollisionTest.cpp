#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/collision/SelfCollision.h"
#include "crowdcloth/core/RectanglePanel.h"
#include "self_collision/TriangleIntersections.h"

namespace cc::collision {
namespace {

using Triangles = std::vector<std::array<uint32_t, 3>>;

SelfCollision makeSelf(const Triangles& tris, uint32_t vertexCount, const SelfCollisionSettings& settings = {}) {
    auto self = SelfCollision::create(tris, vertexCount, settings);
    EXPECT_TRUE(self.isOk()) << self.status().message();
    return std::move(self.value());
}

// ---- Broad phase (TESTPLAN C3) ----

bool boxesOverlap(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1, std::initializer_list<uint32_t> a,
                  std::initializer_list<uint32_t> b, double margin) {
    Vec3 alo = Vec3::Constant(1e300), ahi = -alo, blo = alo, bhi = -alo;
    for (uint32_t v : a) {
        alo = alo.cwiseMin(x0[v]).cwiseMin(x1[v]);
        ahi = ahi.cwiseMax(x0[v]).cwiseMax(x1[v]);
    }
    for (uint32_t v : b) {
        blo = blo.cwiseMin(x0[v]).cwiseMin(x1[v]);
        bhi = bhi.cwiseMax(x0[v]).cwiseMax(x1[v]);
    }
    return ((alo.array() - margin) <= bhi.array()).all() && ((blo.array() - margin) <= ahi.array()).all();
}

void checkCandidatesAgainstBruteForce(const Triangles& tris, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                                      double margin) {
    SelfCollisionSettings exhaustive;  // a soup of random triangles is as crowded as cloth never is
    exhaustive.maxPairsPerTriangle = UINT32_MAX;
    SelfCollision self = makeSelf(tris, static_cast<uint32_t>(x0.size()), exhaustive);
    std::vector<std::array<uint32_t, 2>> vf, ee;
    ASSERT_TRUE(self.candidates(x0, x1, margin, vf, ee));
    const std::set<std::array<uint32_t, 2>> vfSet(vf.begin(), vf.end()), eeSet(ee.begin(), ee.end());
    EXPECT_EQ(vfSet.size(), vf.size()) << "duplicate vertex-triangle candidates";
    EXPECT_TRUE(std::is_sorted(vf.begin(), vf.end()));
    EXPECT_TRUE(std::is_sorted(ee.begin(), ee.end()));
    int missing = 0, expected = 0;
    for (uint32_t v = 0; v < x0.size(); ++v) {
        for (uint32_t t = 0; t < tris.size(); ++t) {
            const auto& tri = tris[t];
            if (tri[0] == v || tri[1] == v || tri[2] == v) continue;
            if (!boxesOverlap(x0, x1, {v}, {tri[0], tri[1], tri[2]}, margin)) continue;
            ++expected;
            missing += vfSet.count({v, t}) ? 0 : 1;
        }
    }
    const auto edges = self.edges();
    for (uint32_t e = 0; e < edges.size(); ++e) {
        for (uint32_t f = e + 1; f < edges.size(); ++f) {
            const auto& a = edges[e];
            const auto& b = edges[f];
            if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
            if (!boxesOverlap(x0, x1, {a[0], a[1]}, {b[0], b[1]}, margin)) continue;
            ++expected;
            missing += eeSet.count({e, f}) ? 0 : 1;
        }
    }
    EXPECT_GT(expected, 0);
    EXPECT_EQ(missing, 0) << "of " << expected << " brute-force pairs";
}

TEST(SelfCollisionBroadPhase, RandomSoupCandidatesIncludeAllBruteForcePairs) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const uint32_t n = 300;
    std::vector<Vec3> x0(n), x1(n);
    for (uint32_t v = 0; v < n; ++v) {
        x0[v] = Vec3(unit(rng), unit(rng), unit(rng));
        x1[v] = x0[v] + 0.05 * Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
    }
    Triangles tris;
    for (uint32_t t = 0; t < 200; ++t) {
        const uint32_t a = static_cast<uint32_t>(rng() % n);
        uint32_t b = static_cast<uint32_t>(rng() % n), c = static_cast<uint32_t>(rng() % n);
        if (b == a) b = (a + 1) % n;
        while (c == a || c == b) c = (c + 1) % n;
        tris.push_back({a, b, c});
    }
    checkCandidatesAgainstBruteForce(tris, x0, x1, 0.01);
}

TEST(SelfCollisionBroadPhase, TheTreeAgainstItselfFindsExactlyTheOverlappingPairs) {
    // Boxes of mixed sizes (a few large, as a fast vertex's), refit after moving: the self-descent
    // returns each overlapping pair once, and nothing else; asked for the pairs of marked
    // primitives only, exactly those.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto randomBoxes = [&](std::size_t n) {
        std::vector<Aabb> boxes(n);
        for (Aabb& box : boxes) {
            const Vec3 centre(unit(rng), unit(rng), 0.2 * unit(rng));
            const double half = unit(rng) < 0.05 ? 0.1 : 0.01 + 0.02 * unit(rng);
            box.grow(centre - Vec3::Constant(half));
            box.grow(centre + Vec3::Constant(half));
        }
        return boxes;
    };
    TriangleBvh bvh;
    bvh.build(randomBoxes(500));
    for (int round = 0; round < 2; ++round) {
        const std::vector<Aabb> boxes = randomBoxes(500);
        bvh.refit(boxes);
        std::vector<std::array<uint32_t, 2>> pairs;
        EXPECT_TRUE(bvh.overlappingPairs(pairs));
        std::sort(pairs.begin(), pairs.end());
        EXPECT_EQ(std::adjacent_find(pairs.begin(), pairs.end()), pairs.end()) << "a pair found twice";
        std::vector<std::array<uint32_t, 2>> expected;
        for (uint32_t a = 0; a < boxes.size(); ++a)
            for (uint32_t b = a + 1; b < boxes.size(); ++b)
                if (boxes[a].overlaps(boxes[b])) expected.push_back({a, b});
        EXPECT_GT(expected.size(), 500u);
        EXPECT_EQ(pairs, expected);
        // With a few primitives marked (as vertices that left their cached boxes mark theirs): the
        // same pairs less those where neither is marked.
        std::vector<uint8_t> marked(boxes.size(), 0);
        for (uint8_t& m : marked) m = unit(rng) < 0.05;
        std::vector<std::array<uint32_t, 2>> markedPairs, expectedMarked;
        bvh.overlappingPairs(marked, markedPairs);
        std::sort(markedPairs.begin(), markedPairs.end());
        for (const auto& p : expected)
            if (marked[p[0]] || marked[p[1]]) expectedMarked.push_back(p);
        EXPECT_GT(expectedMarked.size(), 10u);
        EXPECT_EQ(markedPairs, expectedMarked);
        // Capped: the descent stops soon after the cap, and says so; at the exact count it does not.
        std::vector<std::array<uint32_t, 2>> capped{{0, 0}};  // appends: the cap counts new pairs
        EXPECT_FALSE(bvh.overlappingPairs(capped, expected.size() / 4));
        EXPECT_GT(capped.size(), expected.size() / 4);
        EXPECT_LT(capped.size(), expected.size() / 2);
        capped.clear();
        EXPECT_TRUE(bvh.overlappingPairs(capped, expected.size()));
        EXPECT_EQ(capped.size(), expected.size());
        std::vector<std::array<uint32_t, 2>> cappedMarked;
        EXPECT_FALSE(bvh.overlappingPairs(marked, cappedMarked, expectedMarked.size() / 2));
        EXPECT_TRUE(bvh.overlappingPairs(marked, cappedMarked, SIZE_MAX));
    }
}

TEST(SelfCollisionBroadPhase, DegenerateMeshCandidatesIncludeAllBruteForcePairs) {
    // Two coplanar sheets on top of each other (duplicate vertex positions), zero motion, plus a
    // zero-area triangle: every box touches many others exactly.
    const ClothMesh sheet = RectanglePanel{1.0, 1.0, 6, 6}.build().value();
    std::vector<Vec3> x;
    Triangles tris;
    for (int copy = 0; copy < 2; ++copy) {
        const uint32_t base = static_cast<uint32_t>(x.size());
        x.insert(x.end(), sheet.positions.begin(), sheet.positions.end());
        for (const auto& t : sheet.triangles) tris.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    x.push_back(Vec3(0.1, 0.1, 0.0));
    x.push_back(Vec3(0.2, 0.2, 0.0));
    x.push_back(Vec3(0.3, 0.3, 0.0));
    const uint32_t last = static_cast<uint32_t>(x.size());
    tris.push_back({last - 3, last - 2, last - 1});
    checkCandidatesAgainstBruteForce(tris, x, x, 0.0);
    checkCandidatesAgainstBruteForce(tris, x, x, 1e-3);
}

// ---- Small handcrafted contacts (TESTPLAN C7) ----

// Triangle 0 = (0, 1, 2) in z = 0; triangle 1 = (3, 4, 5) above it, tilted so only vertex 3 is low.
struct TwoTriangles {
    Triangles tris{{0, 1, 2}, {3, 4, 5}};
    std::vector<Vec3> x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                         Vec3(0.25, 0.25, 0.5), Vec3(1.25, 0.25, 1.0), Vec3(0.25, 1.25, 1.0)};
    std::vector<double> masses = std::vector<double>(6, 1.0);
};

TEST(SelfCollision, VertexDrivenThroughFaceIsStoppedAndStaysAbove) {
    TwoTriangles s;
    std::vector<Vec3> x1 = s.x0;
    for (int v = 3; v < 6; ++v) x1[v].z() -= 1.0;  // vertex 3 would end at z = -0.5
    SelfCollision self = makeSelf(s.tris, 6);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(s.x0, x1, s.masses, stats).isOk());
    EXPECT_GT(stats.firstPassCollisions, 0u);
    for (const Vec3& p : x1) EXPECT_TRUE(isFinite(p));
    // Vertex 3 stays above the lower triangle, which it was over.
    const double lowerPlane = (x1[1] - x1[0]).cross(x1[2] - x1[0]).normalized().dot(x1[3] - x1[0]);
    EXPECT_GT(lowerPlane, 0.0);
    // Momentum along z is conserved by the impulses (equal masses).
    double before = 0.0, after = 0.0;
    for (int v = 0; v < 6; ++v) {
        before += s.x0[v].z() + (v >= 3 ? -1.0 : 0.0);
        after += x1[v].z();
    }
    EXPECT_NEAR(after, before, 1e-9);
}

TEST(SelfCollision, PinnedTriangleIsNeverMoved) {
    TwoTriangles s;
    std::vector<Vec3> x1 = s.x0;
    for (int v = 3; v < 6; ++v) x1[v].z() -= 1.0;
    s.masses[0] = 0.0;  // pinned
    s.masses[1] = std::numeric_limits<double>::infinity();
    s.masses[2] = 0.0;
    SelfCollision self = makeSelf(s.tris, 6);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(s.x0, x1, s.masses, stats).isOk());
    for (int v = 0; v < 3; ++v) EXPECT_EQ(x1[v], s.x0[v]);
    EXPECT_GT(x1[3].z(), 0.0);
}

TEST(SelfCollision, VertexOnFaceWithoutMotionGetsNoImpulse) {
    TwoTriangles s;
    s.x0[3] = Vec3(0.25, 0.25, 0.0);  // exactly on the lower face
    std::vector<Vec3> x1 = s.x0;
    SelfCollision self = makeSelf(s.tris, 6);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(s.x0, x1, s.masses, stats).isOk());
    for (int v = 0; v < 6; ++v) EXPECT_EQ(x1[v], s.x0[v]) << "vertex " << v;
    EXPECT_EQ(stats.failSafeActivations, 0u);
}

TEST(SelfCollision, VertexOnEdgeWithoutMotionGetsNoImpulse) {
    TwoTriangles s;
    s.x0[3] = Vec3(0.5, 0.0, 0.0);  // exactly on edge (0, 1)
    std::vector<Vec3> x1 = s.x0;
    SelfCollision self = makeSelf(s.tris, 6);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(s.x0, x1, s.masses, stats).isOk());
    for (int v = 0; v < 6; ++v) EXPECT_EQ(x1[v], s.x0[v]) << "vertex " << v;
}

TEST(SelfCollision, ParallelEdgesInsideThicknessArePushedApartAlongTheirNormalOnly) {
    // Two separate triangles whose edges (0,1) and (3,4) are parallel, 1 mm apart in z.
    const Triangles tris{{0, 1, 2}, {3, 4, 5}};
    const std::vector<Vec3> x0{Vec3(0, 0, 0),     Vec3(1, 0, 0),     Vec3(0.5, -1, 0),
                               Vec3(0, 0, 0.001), Vec3(1, 0, 0.001), Vec3(0.5, 1, 0.001)};
    std::vector<Vec3> x1 = x0;
    SelfCollisionSettings settings;
    settings.thickness = 0.003;
    SelfCollision self = makeSelf(tris, 6, settings);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(x0, x1, std::vector<double>(6, 1.0), stats).isOk());
    EXPECT_GT(stats.repulsions, 0u);
    for (int v = 0; v < 6; ++v) {
        EXPECT_TRUE(isFinite(x1[v]));
        EXPECT_EQ(x1[v].x(), x0[v].x());
        EXPECT_EQ(x1[v].y(), x0[v].y());
    }
    EXPECT_GT(x1[3].z() - x1[0].z(), 0.001);  // the gap grew
    // Far apart (twice the thickness), nothing happens.
    std::vector<Vec3> far = x0;
    for (int v = 3; v < 6; ++v) far[v].z() = 0.006;
    std::vector<Vec3> farEnd = far;
    ASSERT_TRUE(self.resolve(far, farEnd, std::vector<double>(6, 1.0), stats).isOk());
    EXPECT_EQ(farEnd, far);
    EXPECT_EQ(stats.repulsions, 0u);
}

TEST(SelfCollision, PairsSlidingAlongTheirSeparationNeedNoContinuousTest) {
    // Two parallel triangles 5 mm apart (beyond the thickness) in a plane tilted 45 degrees, so
    // their boxes overlap; the upper slides 30 cm along them over the step. Their relative motion is
    // far larger than the gap (the first cheap proof fails), but along the normal every vertex of one
    // stays 5 mm from every vertex of the other at both ends, which holds throughout the linear
    // motion: no continuous test runs and nothing moves.
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.25 * 3.141592653589793, Vec3::UnitX()).toRotationMatrix();
    Triangles tris{{0, 1, 2}, {3, 4, 5}};
    std::vector<Vec3> x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                         Vec3(0.1, 0.1, 0.005), Vec3(1.1, 0.1, 0.005), Vec3(0.1, 1.1, 0.005)};
    std::vector<Vec3> x1 = x0;
    for (int v = 3; v < 6; ++v) x1[v].x() += 0.3;
    for (std::vector<Vec3>* x : {&x0, &x1})
        for (Vec3& p : *x) p = tilt * p;
    const std::vector<Vec3> expected = x1;
    SelfCollision self = makeSelf(tris, 6);
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(x0, x1, std::vector<double>(6, 1.0), stats).isOk());
    EXPECT_GT(stats.ccdTests, 0u);
    EXPECT_EQ(stats.ccdBoxes, 0u);
    EXPECT_EQ(stats.firstPassCollisions, 0u);
    EXPECT_EQ(x1, expected);
}

/// Two n x n grids of 1/n m squares, the upper `gap` [m] above the lower, as one mesh.
struct TwoLayers {
    Triangles tris;
    std::vector<Vec3> x0;
    TwoLayers(int n, double gap) {
        for (int layer = 0; layer < 2; ++layer) {
            const uint32_t first = static_cast<uint32_t>(x0.size());
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) x0.push_back(Vec3(double(i) / n, double(j) / n, layer * gap));
            auto at = [&](int i, int j) { return first + uint32_t(j * (n + 1) + i); };
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    tris.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                    tris.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
                }
        }
    }
};

TEST(SelfCollision, ResolveAfterTheSeparatingPlanesGivesTheResultOfItsOwnSearch) {
    // resolve() filters the pairs separatingPlanes() found for the same x0 and searches only around
    // the vertices that ended outside their look-ahead boxes: the result must be the one of a
    // collider that searched everything itself, bit for bit, whether a few vertices or most left
    // their boxes (then it searches everything too).
    const TwoLayers s(12, 0.004);
    const uint32_t n = static_cast<uint32_t>(s.x0.size());
    const double dt = 1.0 / 60;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> speed(-0.1, 0.1);
    for (const double leaving : {0.05, 0.6}) {
        std::vector<Vec3> velocities(n), x1(n);
        std::bernoulli_distribution leaves(leaving);
        uint32_t left = 0;
        for (uint32_t v = 0; v < n; ++v) {
            velocities[v] = Vec3(speed(random), speed(random), speed(random));
            x1[v] = s.x0[v] + dt * velocities[v];
            if (!leaves(random)) continue;
            x1[v].z() += v < n / 2 ? 0.01 : -0.01;  // through the other layer, out of its box
            ++left;
        }
        SCOPED_TRACE(std::to_string(left) + " of " + std::to_string(n) + " vertices leave their boxes");
        SelfCollision planned = makeSelf(s.tris, n);
        SelfCollision alone = makeSelf(s.tris, n);
        std::vector<Contact> planes;
        ASSERT_TRUE(planned.separatingPlanes(s.x0, velocities, dt, {}, planes).isOk());
        std::vector<Vec3> x1Planned = x1, x1Alone = x1;
        const std::vector<double> masses(n, 1.0);
        SelfCollisionStats withPlanes, withoutPlanes;
        ASSERT_TRUE(planned.resolve(s.x0, x1Planned, masses, withPlanes).isOk());
        ASSERT_TRUE(alone.resolve(s.x0, x1Alone, masses, withoutPlanes).isOk());
        EXPECT_GT(withPlanes.firstPassCollisions, 0u);
        EXPECT_EQ(x1Planned, x1Alone);
        EXPECT_EQ(withPlanes.ccdTests, withoutPlanes.ccdTests);
        EXPECT_EQ(withPlanes.firstPassCollisions, withoutPlanes.firstPassCollisions);
        EXPECT_EQ(withPlanes.impulseIterations, withoutPlanes.impulseIterations);
        EXPECT_GE(withoutPlanes.broadPhases, 1u);
        if (leaving < 0.25) {
            EXPECT_EQ(withPlanes.broadPhases, 0u);  // every pass served by the planes' pairs
        } else {
            EXPECT_GE(withPlanes.broadPhases, 1u);
        }
    }
}

TEST(SelfCollision, AResolveAfterACleanOneFromTheSameStartTestsOnlyWhatMovedSince) {
    // The engine resolves, lets the strain limit move a few vertices, and resolves again from the
    // same x0: the second call tests only pairs with a vertex that moved since the first ended
    // clear, and must give the result, bit for bit, of a collider that tests everything.
    const TwoLayers s(12, 0.004);
    const uint32_t n = static_cast<uint32_t>(s.x0.size());
    std::mt19937 random(5);
    std::uniform_real_distribution<double> speed(-0.1, 0.1);
    std::bernoulli_distribution through(0.05);
    std::vector<Vec3> x1(n);
    for (uint32_t v = 0; v < n; ++v) {
        x1[v] = s.x0[v] + Vec3(speed(random), speed(random), speed(random)) / 60.0;
        if (through(random)) x1[v].z() += v < n / 2 ? 0.01 : -0.01;  // through the other layer
    }
    const std::vector<double> masses(n, 1.0);
    SelfCollision continuing = makeSelf(s.tris, n);
    SelfCollisionStats first;
    ASSERT_TRUE(continuing.resolve(s.x0, x1, masses, first).isOk());
    ASSERT_GT(first.firstPassCollisions, 0u);
    ASSERT_EQ(first.unresolved, 0u);
    // A few vertices of the upper layer pulled back down through the lower one.
    std::vector<Vec3> moved = x1;
    for (uint32_t v = n / 2; v < n; v += 41) moved[v].z() = -0.01;
    std::vector<Vec3> x1Continued = moved, x1Fresh = moved;
    SelfCollision fresh = makeSelf(s.tris, n);
    SelfCollisionStats continued, alone;
    ASSERT_TRUE(continuing.resolve(s.x0, x1Continued, masses, continued).isOk());
    ASSERT_TRUE(fresh.resolve(s.x0, x1Fresh, masses, alone).isOk());
    EXPECT_GT(alone.firstPassCollisions, 0u);
    EXPECT_EQ(continued.firstPassCollisions, alone.firstPassCollisions);
    EXPECT_EQ(x1Continued, x1Fresh);
    EXPECT_LT(continued.ccdTests, alone.ccdTests / 2);
    // From another start it tests everything again.
    std::vector<Vec3> otherStart = s.x0;
    otherStart[0].x() += 1e-6;
    std::vector<Vec3> x1Other = moved, x1OtherFresh = moved;
    SelfCollision otherFresh = makeSelf(s.tris, n);
    SelfCollisionStats other, otherAlone;
    ASSERT_TRUE(continuing.resolve(otherStart, x1Other, masses, other).isOk());
    ASSERT_TRUE(otherFresh.resolve(otherStart, x1OtherFresh, masses, otherAlone).isOk());
    EXPECT_EQ(other.ccdTests, otherAlone.ccdTests);
    EXPECT_EQ(x1Other, x1OtherFresh);
}

TEST(SelfCollision, ACrumpledGarmentIsLeftToItselfAtABoundedCost) {
    // A 24 x 24 sheet crumpled into a 2 cm ball (as a coarse level's fold prolonged to a fine one
    // leaves it): every triangle's box meets hundreds of others. The planes and the resolve stop
    // at maxPairsPerTriangle instead of testing a million pairs, say so, and change nothing; the
    // same sheet spread out is searched as before.
    const int n = 24;
    Triangles tris;
    std::vector<Vec3> flat, ball;
    std::mt19937 random(9);
    std::uniform_real_distribution<double> within(-0.01, 0.01);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            flat.push_back(Vec3(double(i) / n, double(j) / n, 0.0));
            ball.push_back(Vec3(within(random), within(random), within(random)));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            tris.push_back({a, b, d});
            tris.push_back({a, d, c});
        }
    const uint32_t count = static_cast<uint32_t>(flat.size());
    const std::vector<Vec3> still(count, Vec3::Zero());
    const std::vector<double> masses(count, 1.0);
    SelfCollision self = makeSelf(tris, count);
    std::vector<Contact> planes;
    const auto start = std::chrono::steady_clock::now();
    ASSERT_TRUE(self.separatingPlanes(ball, still, 1.0 / 60, {}, planes).isOk());
    EXPECT_TRUE(self.crowded());
    EXPECT_TRUE(planes.empty());
    std::vector<Vec3> x1 = ball;
    for (Vec3& p : x1) p += Vec3(within(random), within(random), within(random));
    const std::vector<Vec3> before = x1;
    SelfCollisionStats stats;
    ASSERT_TRUE(self.resolve(ball, x1, masses, stats).isOk());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(stats.crowded, 1u);
    EXPECT_EQ(stats.ccdTests, 0u);
    EXPECT_EQ(x1, before);
    std::printf("[ crumpled 24 x 24 sheet ] planes and resolve stopped in %.1f ms\n", 1e3 * seconds);
    // Spread out, the same collider searches and is not crowded.
    ASSERT_TRUE(self.separatingPlanes(flat, still, 1.0 / 60, {}, planes).isOk());
    EXPECT_FALSE(self.crowded());
    std::vector<Vec3> flatEnd = flat;
    ASSERT_TRUE(self.resolve(flat, flatEnd, masses, stats).isOk());
    EXPECT_EQ(stats.crowded, 0u);
    EXPECT_FALSE(self.crowded());
    // Without the cap the ball is searched in full: what the cap saves.
    SelfCollisionSettings exhaustive;
    exhaustive.maxPairsPerTriangle = UINT32_MAX;
    SelfCollision unbounded = makeSelf(tris, count, exhaustive);
    std::vector<std::array<uint32_t, 2>> vf, ee;
    ASSERT_TRUE(unbounded.candidates(ball, ball, 0.003, vf, ee));
    EXPECT_GT(vf.size() + ee.size(), 64u * tris.size());
}

TEST(SelfCollision, BadInputNamesTheProblem) {
    TwoTriangles s;
    SelfCollision self = makeSelf(s.tris, 6);
    SelfCollisionStats stats;
    std::vector<Vec3> x1 = s.x0;
    x1[4].y() = std::nan("");
    Status status = self.resolve(s.x0, x1, s.masses, stats);
    EXPECT_FALSE(status.isOk());
    EXPECT_NE(status.message().find("vertex 4"), std::string::npos) << status.message();
    x1 = s.x0;
    s.masses[2] = -1.0;
    status = self.resolve(s.x0, x1, s.masses, stats);
    EXPECT_NE(status.message().find("vertex 2"), std::string::npos) << status.message();
    std::vector<Vec3> tooShort(3);
    EXPECT_FALSE(self.resolve(s.x0, tooShort, s.masses, stats).isOk());
    EXPECT_FALSE(SelfCollision::create(Triangles{{0, 1, 7}}, 3, {}).isOk());
    EXPECT_FALSE(SelfCollision::create(Triangles{{0, 1, 1}}, 3, {}).isOk());
    SelfCollisionSettings bad;
    bad.ccdGap = 2 * bad.thickness;
    EXPECT_NE(bad.validate().message().find("ccdGap"), std::string::npos);
    SelfCollisionSettings uncapped;
    uncapped.maxPairsPerTriangle = 0;
    EXPECT_NE(uncapped.validate().message().find("maxPairsPerTriangle"), std::string::npos);
}

// ---- Garments (TESTPLAN C6): zero intersecting triangle pairs after every step ----

struct GarmentRun {
    int steps = 0;
    int intersectingAfterAnyStep = 0;
    uint32_t failSafe = 0, zoneIterations = 0, stopped = 0, unresolved = 0, maxImpulseIterations = 0;
    uint32_t capped = 0, ccdTests = 0;
    uint64_t boxes = 0;
    double resolveSeconds = 0.0;
    uint64_t hash = 0;
};

/// Steps the cloth solver, then self-collision on (positions before, positions after), writing back
/// positions and velocities as the engine does.
template <typename BeforeStep>
GarmentRun runGarment(cloth::ClothSimulation& sim, const ClothMesh& mesh, const SelfCollisionSettings& settings,
                      int steps, double dt, const std::vector<uint8_t>& pinned, BeforeStep beforeStep) {
    GarmentRun run;
    SelfCollision self = makeSelf(mesh.triangles, static_cast<uint32_t>(mesh.vertexCount()), settings);
    cloth::ClothState& state = sim.state();
    EXPECT_EQ(test::countIntersectingPairs(state.positions, mesh.triangles), 0) << "scene must start clean";
    std::vector<double> masses = state.masses;
    for (std::size_t v = 0; v < masses.size(); ++v) {
        if (pinned[v]) masses[v] = 0.0;
    }
    for (int step = 0; step < steps; ++step) {
        beforeStep(step);
        const std::vector<Vec3> x0 = state.positions;
        const Status stepped = sim.step(dt);
        EXPECT_TRUE(stepped.isOk()) << stepped.message();
        if (!stepped.isOk()) break;
        std::vector<Vec3> x1 = state.positions;
        SelfCollisionStats stats;
        const auto clockStart = std::chrono::steady_clock::now();
        const Status resolved = self.resolve(x0, x1, masses, stats);
        run.resolveSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - clockStart).count();
        run.capped += stats.cappedTests;
        run.ccdTests += stats.ccdTests;
        run.boxes += stats.ccdBoxes;
        EXPECT_TRUE(resolved.isOk()) << resolved.message();
        for (std::size_t v = 0; v < x1.size(); ++v) {
            state.positions[v] = x1[v];
            state.velocities[v] = (x1[v] - x0[v]) / dt;
        }
        run.failSafe += stats.failSafeActivations;
        run.zoneIterations += stats.zoneIterations;
        run.stopped += stats.stoppedVertices;
        run.unresolved += stats.unresolved;
        run.maxImpulseIterations = std::max(run.maxImpulseIterations, stats.impulseIterations);
        const int crossings = test::countIntersectingPairs(state.positions, mesh.triangles);
        if (crossings > 0) {
            ++run.intersectingAfterAnyStep;
            ADD_FAILURE() << crossings << " intersecting triangle pairs after step " << step;
            break;
        }
        ++run.steps;
    }
    run.hash = state.hash();
    return run;
}

void printRun(const char* name, const GarmentRun& run) {
    std::printf("[ self-collision %s ] %d steps clean; fail-safe steps %u, zone passes %u, stopped vertices %u, "
                "unresolved %u, max impulse passes %u; %u continuous tests (%u capped, %llu boxes), %.1f ms per step\n",
                name, run.steps, run.failSafe, run.zoneIterations, run.stopped, run.unresolved,
                run.maxImpulseIterations, run.ccdTests, run.capped, static_cast<unsigned long long>(run.boxes), 1e3 * run.resolveSeconds / std::max(1, run.steps));
}

TEST(SelfCollisionGarment, SheetDroppedOnFloorFoldsWithoutIntersections) {
    // A 0.6 m sheet held 40 degrees from vertical, its lower edge 2 cm above the floor: it lands,
    // buckles and folds over onto itself.
    RectanglePanel panel;
    panel.width = panel.height = 0.6;
    panel.columns = panel.rows = 16;
    panel.origin = Vec3(-0.3, 0.02, 0.0);
    const double tilt = 40.0 * M_PI / 180.0;
    panel.vAxis = Vec3(0.0, std::cos(tilt), std::sin(tilt));
    const ClothMesh mesh = panel.build().value();
    cloth::ClothMaterial material;
    material.bendStiffness = 1e-6;
    auto sim = cloth::ClothSimulation::create(mesh, material, cloth::SimulationSettings{}).value();
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        ASSERT_TRUE(sim->constraints().setContactPlane(v, Vec3::Zero(), Vec3::UnitY()).isOk());
    }
    SelfCollisionSettings settings;
    settings.thickness = 4e-3;
    const GarmentRun run = runGarment(*sim, mesh, settings, 90, 1.0 / 60, std::vector<uint8_t>(mesh.vertexCount(), 0),
                                      [](int) {});
    printRun("sheet drop", run);
    EXPECT_EQ(run.steps, 90);
    EXPECT_EQ(run.unresolved, 0u);
    // It did fold: the sheet now lies within a few centimetres of the floor.
    double top = 0.0;
    for (const Vec3& p : sim->state().positions) top = std::max(top, p.y());
    EXPECT_LT(top, 0.15);
}

TEST(SelfCollisionGarment, TwistedTubeStaysFreeOfIntersections) {
    // An open tube (330 degrees of a 6 cm radius cylinder, 0.3 m long) pinned at both rings; the top
    // ring turns by 300 degrees and sinks 8 cm, so the middle twists and collapses onto itself.
    const double radius = 0.06, length = 0.3, wrap = 330.0 * M_PI / 180.0;
    RectanglePanel panel;
    panel.width = radius * wrap;
    panel.height = length;
    panel.columns = 20;
    panel.rows = 12;
    ClothMesh mesh = panel.build().value();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const Vec2 uv = mesh.restPositions[v];
        const double angle = uv.x() / radius;
        mesh.positions[v] = Vec3(radius * std::cos(angle), uv.y(), radius * std::sin(angle));
    }
    cloth::ClothMaterial material;
    material.bendStiffness = 1e-6;
    auto sim = cloth::ClothSimulation::create(mesh, material, cloth::SimulationSettings{}).value();
    std::vector<uint8_t> pinned(mesh.vertexCount(), 0);
    std::vector<uint32_t> topRing;
    for (uint32_t i = 0; i <= panel.columns; ++i) {
        const uint32_t bottom = panel.vertexIndex(i, 0), top = panel.vertexIndex(i, panel.rows);
        ASSERT_TRUE(sim->constraints().pin(bottom, mesh.positions[bottom]).isOk());
        pinned[bottom] = pinned[top] = 1;
        topRing.push_back(top);
    }
    const int steps = 120;
    const double dt = 1.0 / 60, turn = 300.0 * M_PI / 180.0, sink = 0.08;
    auto drive = [&](int step) {
        const double s = std::min(1.0, (step + 1) / 90.0);
        const Eigen::AngleAxisd spin(turn * s, Vec3::UnitY());
        for (uint32_t v : topRing) {
            Vec3 p = spin * mesh.positions[v];
            p.y() -= sink * s;
            (void)sim->constraints().setTarget(v, p);
        }
    };
    SelfCollisionSettings settings;
    settings.thickness = 3e-3;
    const GarmentRun run = runGarment(*sim, mesh, settings, steps, dt, pinned, drive);
    printRun("twisted tube", run);
    EXPECT_EQ(run.steps, steps);
    EXPECT_EQ(run.unresolved, 0u);
}

TEST(SelfCollisionGarment, ResultDoesNotDependOnThreadCount) {
    RectanglePanel panel;
    panel.width = panel.height = 0.4;
    panel.columns = panel.rows = 10;
    panel.origin = Vec3(-0.2, 0.02, 0.0);
    panel.vAxis = Vec3(0.0, std::cos(0.6), std::sin(0.6));
    const ClothMesh mesh = panel.build().value();
    uint64_t hashes[2];
    for (int threads = 1; threads <= 2; ++threads) {
        auto sim = cloth::ClothSimulation::create(mesh, cloth::ClothMaterial{}, cloth::SimulationSettings{}).value();
        for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
            ASSERT_TRUE(sim->constraints().setContactPlane(v, Vec3::Zero(), Vec3::UnitY()).isOk());
        }
        SelfCollisionSettings settings;
        settings.parallel.maxThreads = threads;
        settings.parallel.minParallel = 1;
        hashes[threads - 1] =
            runGarment(*sim, mesh, settings, 40, 1.0 / 60, std::vector<uint8_t>(mesh.vertexCount(), 0), [](int) {})
                .hash;
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

} // namespace
} // namespace cc::collision
