#include <random>

#include <gtest/gtest.h>

#include "crowdcloth/lod/GarmentHierarchy.h"
#include "lod/MeshChecks.h"

namespace cc::lod {
namespace {

struct Case {
    const char* name;
    GarmentPattern pattern;
    test::GarmentExpectation expect;
};

std::vector<Case> garments() {
    std::vector<Case> cases;
    cases.push_back({"cape", GarmentPattern::cape(1.2, 0.9, 0.3).value(), {1.2 * 0.9, 2 * (1.2 + 0.9), 1}});
    cases.push_back({"skirt", GarmentPattern::skirt(1.2, 0.6, 0.3).value(), {1.2 * 0.6, 2 * 1.2, 0}});
    cases.push_back({"dress", GarmentPattern::dress(0.6, 0.9, 0.3).value(), {2 * 0.6 * 0.9, 4 * 0.6, 0}});
    cases.push_back(
        {"poncho", GarmentPattern::poncho(0.9, 0.6, 0.2, 0.3).value(), {2 * 0.9 * 0.6, 2 * 0.9 + 4 * 0.6, 1}});
    return cases;
}

struct Snapshot {
    std::vector<uint32_t> triangles;
    std::vector<double> masses;
    std::vector<Vec3> positions;
};

Snapshot snapshot(const GarmentHierarchy& h) {
    Snapshot s{h.activeTriangles(), {}, {}};
    for (uint32_t v = 0; v < h.vertexCount(); ++v) {
        s.masses.push_back(h.mass(v));
        s.positions.push_back(h.position(v));
    }
    return s;
}

TEST(GarmentHierarchy, BaseMeshIsConformingForEveryGarment) {
    for (const Case& c : garments()) {
        auto h = GarmentHierarchy::create(c.pattern, HierarchySettings{});
        ASSERT_TRUE(h.isOk()) << c.name << ": " << h.status().message();
        EXPECT_EQ(test::checkConforming(h.value(), c.expect), "") << c.name;
        EXPECT_NEAR(h.value().totalMass(), 0.15 * c.expect.area, 1e-15) << c.name;
    }
}

TEST(GarmentHierarchy, UniformLevelsHaveTheClosedFormCounts) {
    const auto pattern = GarmentPattern::cape(1.0, 1.0, 0.25).value();  // 4 x 4 squares, 32 triangles
    auto h = GarmentHierarchy::create(pattern, HierarchySettings{}).value();
    for (uint32_t level : {3u, 0u, 6u, 1u, 4u}) {
        ASSERT_TRUE(h.setUniformLevel(level));
        EXPECT_EQ(h.activeTriangleCount(), 32u << level);
        // Even levels are (4 * 2^(L/2))^2 squares; odd levels add the square centres.
        const uint32_t n = 4u << (level / 2);
        const uint32_t vertices = level % 2 == 0 ? (n + 1) * (n + 1) : (n + 1) * (n + 1) + n * n;
        EXPECT_EQ(h.activeVertexCount(), vertices) << "level " << level;
        EXPECT_EQ(test::checkConforming(h, {1.0, 4.0, 1}), "") << "level " << level;
    }
    // The render mesh is uniform level 6 whatever is active.
    EXPECT_EQ(h.renderTriangles().size(), 32u << 6);
    EXPECT_EQ(h.renderVertexCount(), 33u * 33u);
}

// 10,000 random refine/coarsen operations per garment: conforming, manifold, neighbour levels within
// one, mass exact and momentum conserved after every operation; a refine undone by merging its
// diamonds in reverse restores the identical mesh.
TEST(GarmentHierarchy, RandomRefineAndCoarsenKeepInvariants) {
    for (const Case& c : garments()) {
        HierarchySettings settings;
        settings.maxLevel = 7;
        settings.renderLevel = 2;
        auto created = GarmentHierarchy::create(c.pattern, settings);
        ASSERT_TRUE(created.isOk()) << created.status().message();
        GarmentHierarchy& h = created.value();
        std::mt19937 rng(1234);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        for (uint32_t v = 0; v < h.vertexCount(); ++v) {
            if (h.isActive(v)) {
                ASSERT_TRUE(h.setState(v, h.position(v), Vec3(unit(rng), unit(rng), unit(rng))));
            }
        }
        const double mass0 = 0.15 * c.expect.area;
        const Vec3 momentum0 = h.totalMomentum();
        double momentumScale = 0.0;
        for (uint32_t v = 0; v < h.vertexCount(); ++v) momentumScale += h.mass(v) * h.velocity(v).norm();
        int restores = 0;
        for (int op = 0; op < 10000; ++op) {
            const std::vector<uint32_t> active = h.activeTriangles();
            const std::vector<uint32_t> mergeable = h.coarsenableVertices();
            // Refine a little more often than coarsen, but stop growing past ~1500 triangles.
            const bool refine = mergeable.empty() || (active.size() < 1500 && rng() % 100 < 55);
            if (op % 97 == 0) {
                // Refine, then merge the split diamonds in reverse: the same mesh comes back.
                const uint32_t t = active[rng() % active.size()];
                if (h.triangle(t).level >= settings.maxLevel) continue;
                const Snapshot before = snapshot(h);
                std::vector<uint32_t> split;
                ASSERT_TRUE(h.refine(t, &split));
                for (auto it = split.rbegin(); it != split.rend(); ++it) ASSERT_TRUE(h.coarsen(*it)) << *it;
                const Snapshot after = snapshot(h);
                ASSERT_EQ(after.triangles, before.triangles) << c.name << " op " << op;
                for (uint32_t v = 0; v < before.masses.size(); ++v) {
                    ASSERT_NEAR(after.masses[v], before.masses[v], 1e-15) << c.name << " vertex " << v;
                    ASSERT_EQ(after.positions[v], before.positions[v]) << c.name << " vertex " << v;
                }
                ++restores;
            } else if (refine) {
                const uint32_t t = active[rng() % active.size()];
                if (h.triangle(t).level >= settings.maxLevel) continue;
                ASSERT_TRUE(h.refine(t)) << c.name << " op " << op;
            } else {
                ASSERT_TRUE(h.coarsen(mergeable[rng() % mergeable.size()])) << c.name << " op " << op;
            }
            ASSERT_NEAR(h.totalMass(), mass0, 1e-12 * mass0) << c.name << " op " << op;
            ASSERT_LE((h.totalMomentum() - momentum0).norm(), 1e-12 * momentumScale) << c.name << " op " << op;
            if (op % 40 == 0 || op == 9999) {
                const std::string problem = test::checkConforming(h, c.expect);
                ASSERT_EQ(problem, "") << c.name << " op " << op;
            }
        }
        EXPECT_GT(restores, 50) << c.name;
        // Every level is reachable from wherever the random walk ended, and back.
        ASSERT_TRUE(h.setUniformLevel(5));
        EXPECT_EQ(test::checkConforming(h, c.expect), "") << c.name;
        ASSERT_TRUE(h.setUniformLevel(0));
        EXPECT_EQ(test::checkConforming(h, c.expect), "") << c.name;
        EXPECT_EQ(h.activeVertexCount(), GarmentHierarchy::create(c.pattern, settings).value().activeVertexCount());
    }
}

TEST(GarmentHierarchy, TubeWrapAndSeamsShareMidpoints) {
    auto h = GarmentHierarchy::create(GarmentPattern::skirt(1.2, 0.6, 0.3).value(), HierarchySettings{}).value();
    // Refining the triangle beside the wrap must split its partner on the other side of the wrap.
    const uint32_t wrap0 = h.baseVertex(0, 0, 0), wrap1 = h.baseVertex(0, 0, 1);
    EXPECT_EQ(wrap0, h.baseVertex(0, 4, 0));
    ASSERT_TRUE(h.setUniformLevel(1));
    uint32_t beside = GarmentHierarchy::kNone;
    for (uint32_t t : h.activeTriangles()) {
        const auto& v = h.triangle(t).vertices;
        if ((v[1] == wrap0 && v[2] == wrap1) || (v[1] == wrap1 && v[2] == wrap0)) beside = t;
    }
    ASSERT_NE(beside, GarmentHierarchy::kNone);
    std::vector<uint32_t> split;
    ASSERT_TRUE(h.refine(beside, &split));
    ASSERT_EQ(split.size(), 1u);  // one diamond, whose two halves sit on either side of the wrap
    int sides = 0;
    for (uint32_t t : h.activeTriangles()) {
        const auto& tri = h.triangle(t);
        if (std::find(tri.vertices.begin(), tri.vertices.end(), split[0]) == tri.vertices.end()) continue;
        sides |= tri.rest[0].x() < 0.6 ? 1 : 2;
    }
    EXPECT_EQ(sides, 3);
    EXPECT_EQ(test::checkConforming(h, {1.2 * 0.6, 2.4, 0}), "");
}

} // namespace
} // namespace cc::lod
