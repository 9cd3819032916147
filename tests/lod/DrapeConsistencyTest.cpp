#include <cstdio>

#include <gtest/gtest.h>

#include "lod/LodSimulation.h"

namespace cc::lod {
namespace {

using test::LodSimulation;

constexpr double kDt = 1.0 / 60.0;

/// A 1 m x 1 m cape lying horizontal at y = 1 m, pinned at the two corners of its far side.
GarmentHierarchy horizontalCape() {
    GarmentPattern pattern = GarmentPattern::cape(1.0, 1.0, 0.25).value();
    pattern.panels[0].vAxis = Vec3::UnitZ();
    pattern.panels[0].origin.y() = 1.0;
    HierarchySettings settings;
    settings.renderLevel = 6;
    settings.maxLevel = 6;
    return GarmentHierarchy::create(pattern, settings).value();
}

LodSimulation simulationOf(GarmentHierarchy& h) {
    LodSimulation run;
    run.hierarchy = &h;
    run.material.damping = 0.01;
    for (uint32_t i : {0u, 4u}) run.pins.push_back({h.baseVertex(0, i, 4), h.position(h.baseVertex(0, i, 4))});
    return run;
}

/// Settles to the static drape: steps with the velocities zeroed every 20 steps (quasi-static
/// relaxation), adapting every `adaptEvery` steps when criteria are given. Returns the render mesh.
std::vector<Vec3> settle(GarmentHierarchy& h, const RefinementSettings* criteria, uint32_t& outMaxVertices) {
    LodSimulation run = simulationOf(h);
    EXPECT_TRUE(run.rebuild());
    outMaxVertices = h.activeVertexCount();
    for (int step = 1; step <= 600; ++step) {
        EXPECT_TRUE(run.step(kDt));
        if (step % 20 == 0) run.stopMotion();
        if (criteria && step % 10 == 0 && step <= 400) {
            auto stats = h.adapt(*criteria, {});
            EXPECT_TRUE(stats.isOk());
            if (stats.value().changed()) {
                EXPECT_TRUE(run.rebuild());
            }
            outMaxVertices = std::max(outMaxVertices, h.activeVertexCount());
        }
    }
    for (int f = 0; f < 10; ++f) h.advanceMorph();
    EXPECT_LT(run.maxSpeed(), 0.05);
    std::vector<Vec3> positions, normals;
    h.renderPositions(positions, normals);
    return positions;
}

/// The uniform level-6 drape, settled once for both tests.
const std::vector<Vec3>& finestDrape(uint32_t& outVertices) {
    static uint32_t vertices = 0;
    static const std::vector<Vec3> drape = [] {
        GarmentHierarchy fine = horizontalCape();
        EXPECT_TRUE(fine.setUniformLevel(6));
        return settle(fine, nullptr, vertices);
    }();
    outVertices = vertices;
    return drape;
}

TEST(DrapeConsistency, CoarseAndFineLevelsDrapeAlike) {
    GarmentHierarchy coarse = horizontalCape();
    ASSERT_TRUE(coarse.setUniformLevel(2));
    uint32_t nCoarse = 0, nFine = 0;
    const std::vector<Vec3> a = settle(coarse, nullptr, nCoarse);
    const std::vector<Vec3>& b = finestDrape(nFine);
    const auto [rms, worst] = test::renderDistance(a, b);
    // The sheet hangs about 1 m deep: "within a few percent" of its size.
    std::printf("L2 (%u vertices) vs L6 (%u vertices): RMS %.4f m, max %.4f m\n", nCoarse, nFine, rms, worst);
    EXPECT_LT(rms, 0.03);
    EXPECT_LT(worst, 0.06);
}

TEST(DrapeConsistency, CurvatureAdaptiveMatchesUniformFinest) {
    GarmentHierarchy adaptive = horizontalCape();
    ASSERT_TRUE(adaptive.setUniformLevel(2));
    RefinementSettings criteria;
    criteria.maxDihedralAngle = 0.08;
    criteria.quietFrames = 5;
    uint32_t nAdaptive = 0, nFine = 0;
    const std::vector<Vec3> a = settle(adaptive, &criteria, nAdaptive);
    const std::vector<Vec3>& b = finestDrape(nFine);
    const auto [rms, worst] = test::renderDistance(a, b);
    std::printf("adaptive (%u vertices at the end, %u at most) vs L6 (%u vertices): RMS %.4f m, max %.4f m\n",
                adaptive.activeVertexCount(), nAdaptive, nFine, rms, worst);
    EXPECT_LT(rms, 0.02);
    EXPECT_LT(worst, 0.04);
    EXPECT_LT(nAdaptive, nFine / 2);
}

} // namespace
} // namespace cc::lod
