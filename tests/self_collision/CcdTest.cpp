#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "crowdcloth/collision/Ccd.h"
#include "self_collision/CcdOracle.h"

namespace cc::collision {
namespace {

using Points = std::array<Vec3, 4>;

CcdOutcome runVf(const Points& start, const Points& end, double thickness, CcdHit& hit) {
    CcdSettings settings;
    settings.thickness = thickness;
    return vertexTriangleCcd(start, end, settings, hit);
}

CcdOutcome runEe(const Points& start, const Points& end, double thickness, CcdHit& hit) {
    CcdSettings settings;
    settings.thickness = thickness;
    return edgeEdgeCcd(start, end, settings, hit);
}

// The default settings resolve time to 1e-6, and the reported toi may only be early.
constexpr double kToiTolerance = 2e-6;

// Triangle in the z = 0 plane, used by the handcrafted vertex-triangle cases.
const Vec3 kA(0.0, 0.0, 0.0), kB(1.0, 0.0, 0.0), kC(0.0, 1.0, 0.0);

TEST(Ccd, VertexFallingThroughFaceHitsAtPlaneCrossing) {
    const Vec3 centre(1.0 / 3, 1.0 / 3, 0.0);
    CcdHit hit;
    ASSERT_EQ(runVf({centre + Vec3(0, 0, 1), kA, kB, kC}, {centre - Vec3(0, 0, 1), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    // The vertex crosses z = 0 at t = 0.5; toi may only undershoot, by the search resolution.
    EXPECT_LE(hit.toi, 0.5);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_NEAR(hit.weights[0], 1.0 / 3, 1e-5);
    EXPECT_NEAR(hit.weights[1], 1.0 / 3, 1e-5);
    EXPECT_NEAR(hit.weights[2], 1.0 / 3, 1e-5);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);  // the vertex came from above
}

TEST(Ccd, ThicknessAdvancesTheTimeOfImpact) {
    const Vec3 centre(0.25, 0.25, 0.0);
    CcdHit hit;
    // Speed 2 m per unit time: contact at distance 0.1 happens at t = (1 - 0.1) / 2.
    ASSERT_EQ(runVf({centre + Vec3(0, 0, 1), kA, kB, kC}, {centre - Vec3(0, 0, 1), kA, kB, kC}, 0.1, hit),
              CcdOutcome::Contact);
    EXPECT_LE(hit.toi, 0.45);
    EXPECT_NEAR(hit.toi, 0.45, kToiTolerance);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);
}

TEST(Ccd, MovingTriangleHitsRestingVertex) {
    // The triangle rises through a resting vertex: only relative motion matters.
    const Vec3 p(0.2, 0.2, 0.0);
    const Vec3 down(0, 0, -1), up(0, 0, 1);
    CcdHit hit;
    ASSERT_EQ(runVf({p, kA + down, kB + down, kC + down}, {p, kA + up, kB + up, kC + up}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);  // the vertex was above the triangle at the start
}

TEST(Ccd, CoplanarVertexEnteringTriangleIsFoundAtTheEdge) {
    // All motion in the triangle's plane: the coplanarity cubic is identically zero here.
    CcdHit hit;
    ASSERT_EQ(runVf({Vec3(-1.0, 0.25, 0), kA, kB, kC}, {Vec3(1.0, 0.25, 0), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_LE(hit.toi, 0.5);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);  // reaches x = 0 (edge ca) at t = 0.5
    EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-12);
}

TEST(Ccd, CoplanarVertexPassingOutsideIsSeparated) {
    CcdHit hit;
    // Slides along y = -0.1, below edge ab, never closer than 0.1.
    EXPECT_EQ(runVf({Vec3(-1, -0.1, 0), kA, kB, kC}, {Vec3(2, -0.1, 0), kA, kB, kC}, 0.01, hit),
              CcdOutcome::Separated);
}

TEST(Ccd, GrazingVertexAtThicknessIsContactAndFartherIsNot) {
    const double eta = 1e-3;
    CcdHit hit;
    // Skims across the face at exactly the thickness: the boundary counts as contact.
    EXPECT_EQ(runVf({Vec3(-1, 0.2, eta), kA, kB, kC}, {Vec3(2, 0.2, eta), kA, kB, kC}, eta, hit),
              CcdOutcome::Contact);
    // At twice the thickness it is clear (the L-infinity false-positive band ends at sqrt(3) eta).
    EXPECT_EQ(runVf({Vec3(-1, 0.2, 2 * eta), kA, kB, kC}, {Vec3(2, 0.2, 2 * eta), kA, kB, kC}, eta, hit),
              CcdOutcome::Separated);
    // Zero thickness: an in-plane path that only grazes corner b = (1, 0, 0) at t = 0.5.
    ASSERT_EQ(runVf({Vec3(0.5, -0.5, 0), kA, kB, kC}, {Vec3(1.5, 0.5, 0), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_LE(hit.toi, 0.5);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_NEAR(hit.weights[1], 1.0, 1e-5);
}

TEST(Ccd, ZeroMotionReportsOnlyExistingContact) {
    CcdHit hit;
    const Vec3 near(0.2, 0.2, 0.5e-3), far(0.2, 0.2, 0.01);
    ASSERT_EQ(runVf({near, kA, kB, kC}, {near, kA, kB, kC}, 1e-3, hit), CcdOutcome::Contact);
    EXPECT_EQ(hit.toi, 0.0);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);
    EXPECT_EQ(runVf({far, kA, kB, kC}, {far, kA, kB, kC}, 1e-3, hit), CcdOutcome::Separated);
    // Exactly on the face, no motion, zero thickness: touching, normal is the face normal.
    const Vec3 on(0.2, 0.2, 0.0);
    ASSERT_EQ(runVf({on, kA, kB, kC}, {on, kA, kB, kC}, 0.0, hit), CcdOutcome::Contact);
    EXPECT_EQ(hit.toi, 0.0);
    EXPECT_NEAR(std::abs(hit.normal.z()), 1.0, 1e-12);
    EXPECT_TRUE(isFinite(hit.normal));
}

TEST(Ccd, ExactHitsAtStartAndEnd) {
    CcdHit hit;
    // Touching at t = 0 and leaving.
    ASSERT_EQ(runVf({Vec3(0.2, 0.2, 0), kA, kB, kC}, {Vec3(0.2, 0.2, 1), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_EQ(hit.toi, 0.0);
    // No side to come from: the normal opposes the motion, so a response stops it rather than
    // letting a possible crossing through.
    EXPECT_NEAR(hit.normal.z(), -1.0, 1e-9);
    // Arriving exactly at t = 1.
    ASSERT_EQ(runVf({Vec3(0.2, 0.2, 1), kA, kB, kC}, {Vec3(0.2, 0.2, 0), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 1.0, kToiTolerance);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);
    // Edge-edge: crossing edges meet exactly at t = 1.
    ASSERT_EQ(runEe({Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                    {Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 1, 0)}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 1.0, kToiTolerance);
}

TEST(Ccd, VertexThroughAnEdgeAndAVertexOfTheTriangle) {
    CcdHit hit;
    // Through the midpoint of edge ab.
    ASSERT_EQ(runVf({Vec3(0.5, 0, 1), kA, kB, kC}, {Vec3(0.5, 0, -1), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_NEAR(hit.weights[0], 0.5, 1e-5);
    EXPECT_NEAR(hit.weights[1], 0.5, 1e-5);
    // Through corner c.
    ASSERT_EQ(runVf({Vec3(0, 1, 1), kA, kB, kC}, {Vec3(0, 1, -1), kA, kB, kC}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.weights[2], 1.0, 1e-5);
}

TEST(Ccd, CrossingEdgesHitWithParametersAndNormal) {
    CcdHit hit;
    // ab along x at height 1 - 2t, cd along y at height 0: they cross at t = 0.5, s = u = 0.25.
    ASSERT_EQ(runEe({Vec3(-0.25, 0, 1), Vec3(0.75, 0, 1), Vec3(0, -0.25, 0), Vec3(0, 0.75, 0)},
                    {Vec3(-0.25, 0, -1), Vec3(0.75, 0, -1), Vec3(0, -0.25, 0), Vec3(0, 0.75, 0)}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_NEAR(hit.weights[0], 0.25, 1e-5);
    EXPECT_NEAR(hit.weights[1], 0.25, 1e-5);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);
}

TEST(Ccd, ParallelEdges) {
    CcdHit hit;
    const double eta = 1e-3;
    // Parallel, sliding along each other 3 thicknesses apart: clear.
    EXPECT_EQ(runEe({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(-1, 0, 3 * eta), Vec3(0, 0, 3 * eta)},
                    {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 3 * eta), Vec3(2, 0, 3 * eta)}, eta, hit),
              CcdOutcome::Separated);
    // Parallel and approaching head-on: contact when 0.1 apart -> t = 0.45 (gap 1 - 2t).
    ASSERT_EQ(runEe({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1)},
                    {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(1, 0, -1)}, 0.1, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.45, kToiTolerance);
    EXPECT_NEAR(hit.normal.z(), -1.0, 1e-9);  // from cd (above) towards ab (below)
    // Collinear edges in one line, end to end and touching at t = 1.
    ASSERT_EQ(runEe({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0)},
                    {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 1.0, kToiTolerance);
    EXPECT_TRUE(isFinite(hit.normal));
    EXPECT_NEAR(hit.normal.x(), -1.0, 1e-9);  // ab is behind cd along x
}

TEST(Ccd, DegenerateTriangleAndEdgeStayFinite) {
    CcdHit hit;
    // Zero-area triangle (a line) crossed by a vertex.
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
    ASSERT_EQ(runVf({Vec3(0.5, 0, 1), a, b, c}, {Vec3(0.5, 0, -1), a, b, c}, 0.0, hit), CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_TRUE(isFinite(hit.normal));
    EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-12);
    // A zero-length edge (a point) hitting an edge.
    ASSERT_EQ(runEe({Vec3(0.5, 0, 1), Vec3(0.5, 0, 1), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                    {Vec3(0.5, 0, -1), Vec3(0.5, 0, -1), Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.0, hit),
              CcdOutcome::Contact);
    EXPECT_NEAR(hit.toi, 0.5, kToiTolerance);
    EXPECT_TRUE(isFinite(hit.normal));
}

TEST(Ccd, NonFiniteInputIsReported) {
    CcdHit hit;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(runVf({Vec3(nan, 0, 0), kA, kB, kC}, {Vec3(0, 0, 0), kA, kB, kC}, 0.0, hit), CcdOutcome::NonFinite);
    EXPECT_EQ(runEe({kA, kB, kC, Vec3(0, 0, 1)}, {kA, kB, kC, Vec3(0, std::numeric_limits<double>::infinity(), 1)},
                    0.0, hit),
              CcdOutcome::NonFinite);
}

TEST(ClosestSegments, InteriorParametersOfSkewEdgesAndNoneWhereAnEndIsClosest) {
    std::array<double, 2> su{-1.0, -1.0};
    // Perpendicular edges one above the other, crossing at their middles.
    ASSERT_TRUE(interiorClosestSegmentParameters(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 1),
                                                 Vec3(0, 1, 1), su));
    EXPECT_DOUBLE_EQ(su[0], 0.5);
    EXPECT_DOUBLE_EQ(su[1], 0.5);
    // The second edge shifted past the first one's end: closest at that end, out untouched.
    su = {-1.0, -1.0};
    EXPECT_FALSE(interiorClosestSegmentParameters(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(3, -1, 1),
                                                  Vec3(3, 1, 1), su));
    EXPECT_EQ(su[0], -1.0);
    // Parallel edges and a point have no interior pair.
    EXPECT_FALSE(interiorClosestSegmentParameters(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                                                  Vec3(1, 1, 0), su));
    EXPECT_FALSE(interiorClosestSegmentParameters(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0),
                                                  Vec3(1, 1, 0), su));
}

TEST(ClosestSegments, InteriorTestAgreesBitForBitWithTheFullComputation) {
    // The quick rejection must never change an answer: random pairs of every kind (crossing,
    // apart, nearly parallel, of very different lengths, degenerate), each answered as
    // closestSegmentParameters() answers it, with its values.
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_real_distribution<double> exponent(-9.0, 0.0);
    auto point = [&](double scale) -> Vec3 {
        return Vec3(unit(random), unit(random), unit(random)) * scale;
    };
    int interior = 0, total = 0;
    for (int trial = 0; trial < 200000; ++trial) {
        const int kind = trial % 5;
        Vec3 a = point(1.0), b = a + point(0.1), c = point(1.0), d = c + point(0.1);
        if (kind == 1) { // near each other, as a garment's candidate pairs are
            c = a + point(0.05);
            d = c + point(0.1);
        } else if (kind == 2) { // nearly parallel
            d = c + (b - a) + point(std::pow(10.0, exponent(random)));
        } else if (kind == 3) { // lengths three orders apart
            d = c + point(1e-4);
        } else if (kind == 4 && trial % 10 == 4) { // a point
            b = a;
        }
        const std::array<double, 2> full = closestSegmentParameters(a, b, c, d);
        const bool inside = full[0] > 0.0 && full[0] < 1.0 && full[1] > 0.0 && full[1] < 1.0;
        std::array<double, 2> su{-1.0, -1.0};
        const bool answered = interiorClosestSegmentParameters(a, b, c, d, su);
        ASSERT_EQ(answered, inside) << "trial " << trial;
        if (answered) {
            ASSERT_EQ(su[0], full[0]) << "trial " << trial;
            ASSERT_EQ(su[1], full[1]) << "trial " << trial;
            ++interior;
        }
        ++total;
    }
    EXPECT_GT(interior, total / 50);
    EXPECT_LT(interior, total / 2);
}

TEST(CcdSettings, ValidateNamesTheField) {
    CcdSettings settings;
    EXPECT_TRUE(settings.validate().isOk());
    settings.distanceTolerance = 0.0;
    EXPECT_NE(settings.validate().message().find("distanceTolerance"), std::string::npos);
    settings = CcdSettings{};
    settings.thickness = -1.0;
    EXPECT_NE(settings.validate().message().find("thickness"), std::string::npos);
}

// ---- Random queries against the brute-force oracle ----

struct RandomCase {
    Points start, end;
    double thickness;
};

/// Families of motions chosen to hit the hard cases often: generic, crossing, coplanar, zero
/// motion, grazing at the thickness and integer (exactly degenerate) coordinates.
RandomCase makeCase(std::mt19937_64& rng, int family) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<int> grid(-2, 2);
    auto random = [&]() { return Vec3(unit(rng), unit(rng), unit(rng)); };
    const double thicknesses[] = {0.0, 1e-3, 2e-2, 0.1};
    RandomCase c;
    c.thickness = thicknesses[std::uniform_int_distribution<int>(0, 3)(rng)];
    for (int i = 0; i < 4; ++i) {
        c.start[i] = random();
        c.end[i] = random();
    }
    switch (family) {
    case 0: break;  // generic
    case 1:         // crossing: point 0 flips through the others' neighbourhood
        c.end[0] = -c.start[0] + 0.1 * random();
        for (int i = 1; i < 4; ++i) c.end[i] = c.start[i] + 0.2 * random();
        break;
    case 2:  // coplanar motion in z = 0
        for (int i = 0; i < 4; ++i) c.start[i].z() = c.end[i].z() = 0.0;
        break;
    case 3:  // zero motion, close to contact
        for (int i = 0; i < 4; ++i) c.start[i] *= 0.3;
        c.end = c.start;
        break;
    case 4: {  // grazing: everything in z = 0 except point 0 (and 1 for edges) near height thickness
        const double h = c.thickness * (1.0 + 0.02 * unit(rng));
        for (int i = 0; i < 4; ++i) c.start[i].z() = c.end[i].z() = 0.0;
        c.start[0].z() = c.end[0].z() = h;
        c.start[1].z() = c.end[1].z() = h;
        break;
    }
    default:  // integer coordinates / 2: coplanar, parallel, on-edge configurations exactly
        for (int i = 0; i < 4; ++i) {
            c.start[i] = Vec3(grid(rng), grid(rng), grid(rng)) * 0.5;
            c.end[i] = rng() % 3 == 0 ? c.start[i] : Vec3(grid(rng), grid(rng), grid(rng)) * 0.5;
        }
        break;
    }
    return c;
}

struct Tally {
    int contacts = 0, clears = 0, ambiguous = 0, falseNegatives = 0, falsePositives = 0, lateToi = 0;
    int capped = 0;
    long long boxes = 0;
};

void runRandom(bool vertexTriangle, int count, uint64_t seed, Tally& tally) {
    std::mt19937_64 rng(seed);
    for (int n = 0; n < count; ++n) {
        const RandomCase c = makeCase(rng, n % 6);
        CcdHit hit;
        CcdSettings settings;
        settings.thickness = c.thickness;
        const CcdOutcome outcome = vertexTriangle ? vertexTriangleCcd(c.start, c.end, settings, hit)
                                                  : edgeEdgeCcd(c.start, c.end, settings, hit);
        ASSERT_NE(outcome, CcdOutcome::NonFinite);
        tally.boxes += hit.boxesChecked;
        tally.capped += hit.capped ? 1 : 0;
        const test::OracleResult oracle = test::bruteForceCcd(vertexTriangle, c.start, c.end, c.thickness);
        switch (oracle.verdict) {
        case test::OracleVerdict::Contact:
            ++tally.contacts;
            if (outcome != CcdOutcome::Contact) {
                ++tally.falseNegatives;
                ADD_FAILURE() << "false negative, case " << n << " family " << n % 6 << " thickness "
                              << c.thickness << " oracle contact at t = " << static_cast<double>(oracle.firstContact);
            } else if (hit.toi > static_cast<double>(oracle.firstContact) + 1e-12) {
                ++tally.lateToi;
                ADD_FAILURE() << "toi " << hit.toi << " after the oracle's contact at "
                              << static_cast<double>(oracle.firstContact) << ", case " << n;
            }
            break;
        case test::OracleVerdict::Clear:
            ++tally.clears;
            if (outcome == CcdOutcome::Contact) ++tally.falsePositives;
            break;
        case test::OracleVerdict::Ambiguous: ++tally.ambiguous; break;
        }
        if (outcome == CcdOutcome::Contact) {
            EXPECT_GE(hit.toi, 0.0);
            EXPECT_LE(hit.toi, 1.0);
            EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-9);
        }
    }
}

void printTally(const char* name, int count, const Tally& t) {
    std::printf("[ CCD %s ] %d cases: %d contacts, %d clear, %d ambiguous; false negatives %d, "
                "false positives %d (%.2f%% of clear), capped %d, mean boxes %.1f\n",
                name, count, t.contacts, t.clears, t.ambiguous, t.falseNegatives, t.falsePositives,
                t.clears > 0 ? 100.0 * t.falsePositives / t.clears : 0.0, t.capped,
                static_cast<double>(t.boxes) / count);
}

TEST(CcdRandom, VertexTriangleHasNoFalseNegatives) {
    Tally tally;
    const int count = 3000;
    runRandom(true, count, 0x5eed0001u, tally);
    printTally("vertex-triangle", count, tally);
    EXPECT_EQ(tally.falseNegatives, 0);
    EXPECT_EQ(tally.lateToi, 0);
    EXPECT_GT(tally.contacts, count / 10);  // the families do produce contacts
    EXPECT_LT(tally.ambiguous, count / 100);
}

TEST(CcdRandom, EdgeEdgeHasNoFalseNegatives) {
    Tally tally;
    const int count = 3000;
    runRandom(false, count, 0x5eed0002u, tally);
    printTally("edge-edge", count, tally);
    EXPECT_EQ(tally.falseNegatives, 0);
    EXPECT_EQ(tally.lateToi, 0);
    EXPECT_GT(tally.contacts, count / 10);
    EXPECT_LT(tally.ambiguous, count / 100);
}

// TESTPLAN C2: moving only up to a fraction of the time of impact is collision-free, so the
// clamped step re-queried with the same settings reports no contact.
TEST(CcdRandom, ClampedMotionIsCollisionFreeWhenQueriedAgain) {
    std::mt19937_64 rng(0x5eed0003u);
    int clamped = 0, failures = 0;
    for (int n = 0; n < 2400; ++n) {
        const bool vertexTriangle = n % 2 == 0;
        const RandomCase c = makeCase(rng, 1 + (n / 2) % 2);  // crossing and coplanar families
        CcdSettings settings;
        settings.thickness = c.thickness;
        CcdHit hit;
        const CcdOutcome outcome = vertexTriangle ? vertexTriangleCcd(c.start, c.end, settings, hit)
                                                  : edgeEdgeCcd(c.start, c.end, settings, hit);
        if (outcome != CcdOutcome::Contact || hit.toi < 1e-3) continue;
        ++clamped;
        Points end;
        for (int i = 0; i < 4; ++i) end[i] = c.start[i] + 0.8 * hit.toi * (c.end[i] - c.start[i]);
        CcdHit again;
        const CcdOutcome second = vertexTriangle ? vertexTriangleCcd(c.start, end, settings, again)
                                                 : edgeEdgeCcd(c.start, end, settings, again);
        if (second != CcdOutcome::Separated) ++failures;
    }
    std::printf("[ CCD repeated ] %d clamped motions re-queried, %d still in contact\n", clamped, failures);
    EXPECT_GT(clamped, 300);
    EXPECT_EQ(failures, 0);
}

} // namespace
} // namespace cc::collision
