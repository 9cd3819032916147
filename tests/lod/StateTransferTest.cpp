#include <cstdio>

#include <gtest/gtest.h>

#include "crowdcloth/cloth/ClothTopology.h"
#include "lod/LodSimulation.h"

namespace cc::lod {
namespace {

using test::LodSimulation;

/// A 1 m x 1 m cape hanging from its top corners, simulated at `level` for `steps` steps.
struct SwingingCape {
    GarmentHierarchy h;
    LodSimulation run;

    explicit SwingingCape(uint32_t level) {
        HierarchySettings settings;
        settings.renderLevel = 6;
        // Lying horizontal at first, so it falls and swings from its pins.
        GarmentPattern pattern = GarmentPattern::cape(1.0, 1.0, 0.25).value();
        pattern.panels[0].vAxis = Vec3::UnitZ();
        pattern.panels[0].origin.y() = 1.0;
        h = GarmentHierarchy::create(pattern, settings).value();
        EXPECT_TRUE(h.setUniformLevel(level));
        run.hierarchy = &h;
        run.pins = {{h.baseVertex(0, 0, 4), h.position(h.baseVertex(0, 0, 4))},
                    {h.baseVertex(0, 4, 4), h.position(h.baseVertex(0, 4, 4))}};
        EXPECT_TRUE(run.rebuild());
    }
};

double kineticEnergy(const GarmentHierarchy& h) { return h.kineticEnergy(); }

TEST(StateTransfer, SwitchingLevelsDoesNotPop) {
    SwingingCape cape(3);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(cape.run.step(1.0 / 60.0));
    GarmentHierarchy& h = cape.h;
    ASSERT_GT(kineticEnergy(h), 0.05);  // the garment is moving
    std::vector<Vec3> before, after, normals;
    for (uint32_t level : {5u, 2u, 4u, 3u}) {
        h.renderPositions(before, normals);
        const double ke = kineticEnergy(h);
        const Vec3 momentum = h.totalMomentum();
        const double mass = h.totalMass();
        ASSERT_TRUE(h.setUniformLevel(level));
        h.renderPositions(after, normals);
        const auto [rms, worst] = test::renderDistance(before, after);
        std::printf("switch to L%u: largest render jump %.2e m, kinetic energy %.4f -> %.4f J\n", level, worst, ke,
                    kineticEnergy(h));
        EXPECT_LT(worst, 1e-6) << "switch to level " << level;
        EXPECT_LT(std::abs(kineticEnergy(h) - ke), 0.01 * ke) << "switch to level " << level;
        EXPECT_LT((h.totalMomentum() - momentum).norm(), 1e-12 * std::sqrt(2.0 * ke * mass)) << level;
        EXPECT_NEAR(h.totalMass(), mass, 1e-15) << level;
        // The solver continues from the transferred state.
        ASSERT_TRUE(cape.run.rebuild());
        for (int i = 0; i < 5; ++i) ASSERT_TRUE(cape.run.step(1.0 / 60.0));
        h.advanceMorph();
    }
}

TEST(StateTransfer, RenderMeshIsTheInterpolationOperatorOnceMorphsFade) {
    SwingingCape cape(2);
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(cape.run.step(1.0 / 60.0));
    GarmentHierarchy& h = cape.h;
    ASSERT_TRUE(h.setUniformLevel(4));
    ASSERT_TRUE(cape.run.rebuild());
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(cape.run.step(1.0 / 60.0));
    ASSERT_TRUE(h.setUniformLevel(3));  // merges leave fading detail
    ASSERT_TRUE(cape.run.rebuild());
    for (uint32_t f = 0; f < h.settings().morphFrames; ++f) h.advanceMorph();
    std::vector<Vec3> render, normals, viaOperator;
    h.renderPositions(render, normals);
    std::vector<uint32_t> ids(h.renderVertexCount());
    for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
    auto op = h.interpolation(cape.run.active, ids);
    ASSERT_TRUE(op.isOk()) << op.status().message();
    op.value().apply(cape.run.active.mesh.positions, viaOperator);
    double worst = 0.0;
    for (uint32_t i = 0; i < ids.size(); ++i) {
        worst = std::max(worst, (render[i] - viaOperator[i]).norm());
        double sum = 0.0;
        for (uint32_t k = op.value().rowStart[i]; k < op.value().rowStart[i + 1]; ++k) sum += op.value().terms[k].weight;
        ASSERT_NEAR(sum, 1.0, 1e-15);
        ASSERT_LE(op.value().rowStart[i + 1] - op.value().rowStart[i], 3u);  // linear in one triangle
    }
    EXPECT_LT(worst, 1e-12);
    // Normals are unit and face the same side as the pattern's +u x +v.
    for (const Vec3& n : normals) EXPECT_NEAR(n.norm(), 1.0, 1e-12);
}

TEST(StateTransfer, SeamAndWrapCopiesConserveMassAndMomentum) {
    for (const auto& pattern : {GarmentPattern::skirt(1.2, 0.6, 0.3).value(), GarmentPattern::dress(0.6, 0.9, 0.3).value()}) {
        auto h = GarmentHierarchy::create(pattern, HierarchySettings{}).value();
        ASSERT_TRUE(h.setUniformLevel(3));
        ActiveMesh active = h.activeMesh();
        ASSERT_TRUE(active.mesh.validate()) << active.mesh.validate().message();
        EXPECT_FALSE(active.welds.empty());
        EXPECT_EQ(active.simToVertex.size(), h.activeVertexCount() + active.welds.size());
        // The solver lumps the same masses from the exported mesh.
        const std::vector<double> lumped = cloth::lumpedMasses(active.mesh, 0.15);
        for (std::size_t i = 0; i < lumped.size(); ++i) ASSERT_NEAR(lumped[i], active.masses[i], 1e-15) << i;
        double mass = 0.0;
        for (double m : active.masses) mass += m;
        EXPECT_NEAR(mass, h.totalMass(), 1e-15);
        // Give the copies different velocities: readState keeps their total momentum.
        std::vector<Vec3> velocities(active.simToVertex.size());
        Vec3 momentum = Vec3::Zero();
        for (std::size_t i = 0; i < velocities.size(); ++i) {
            velocities[i] = Vec3(std::sin(double(i)), std::cos(3.0 * i), 0.1 * double(i % 7));
            momentum += active.masses[i] * velocities[i];
        }
        ASSERT_TRUE(h.readState(active, active.mesh.positions, velocities));
        EXPECT_LT((h.totalMomentum() - momentum).norm(), 1e-13);
        std::vector<Vec3> x, v;
        h.writeState(active, x, v);
        for (const auto& [a, b] : active.welds) EXPECT_EQ(v[a], v[b]);
    }
}

} // namespace
} // namespace cc::lod
