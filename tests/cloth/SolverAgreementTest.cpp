// The implicit step through PCG and through CHOLMOD solve the same filtered system.
#include <gtest/gtest.h>

#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

TEST(SolverAgreement, PcgAndCholmodGiveTheSameStepToThePcgTolerance) {
    // Bring a sheet into motion, then take the same step from the same state with both solvers,
    // with pins, a moving target and contact planes active.
    ClothMaterial material;
    material.damping = 0.01;
    SimulationSettings settings;
    auto source = test::cornerPinnedSheet(test::horizontalSheet(12), material, settings);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(source->step(1.0 / 60.0).isOk());

    for (double tolerance : {1e-4, 1e-8}) {
        std::vector<Vec3> positions[2];
        int kind = 0;
        for (IntegratorKind integrator : {IntegratorKind::ImplicitPcg, IntegratorKind::ImplicitCholmod}) {
            settings.integrator = integrator;
            settings.implicit.pcg.relativeTolerance = tolerance;
            settings.implicit.warmStart = false;
            auto sim = test::cornerPinnedSheet(test::horizontalSheet(12), material, settings);
            sim->state() = source->state();
            ASSERT_TRUE(sim->constraints().setTarget(6, source->state().positions[6] + Vec3(0.01, 0.0, 0.0)).isOk());
            for (uint32_t v = 20; v < 30; ++v) {
                ASSERT_TRUE(sim->constraints().setContactPlane(v, source->state().positions[v], Vec3(0, 1, 0)).isOk());
            }
            ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
            positions[kind++] = sim->state().positions;
        }
        double worst = 0.0, motion = 0.0;
        for (std::size_t i = 0; i < positions[0].size(); ++i) {
            worst = std::max(worst, (positions[0][i] - positions[1][i]).norm());
            motion = std::max(motion, (positions[1][i] - source->state().positions[i]).norm());
        }
        // The difference in dv is bounded by the PCG residual through the condition number; in
        // position it must be a small fraction of the step's own motion.
        EXPECT_LT(worst, 100.0 * tolerance * motion) << "tolerance " << tolerance;
    }
}

TEST(SolverAgreement, CholmodKeepsItsSymbolicAnalysisWhileThePatternHolds) {
    // Contacts and targets change the filters every step but never the sparsity pattern, so the
    // fill-reducing analysis runs once and only the numeric factorisation repeats.
    SimulationSettings settings;
    settings.integrator = IntegratorKind::ImplicitCholmod;
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(8), ClothMaterial{}, settings);
    for (int i = 0; i < 30; ++i) {
        sim->constraints().clearContactPlanes();
        if (i % 2) {
            ASSERT_TRUE(sim->constraints().setContactPlane(10, Vec3(0, 0.5, 0), Vec3::UnitY()).isOk());
        }
        ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
    }
    const auto& implicit = static_cast<const ImplicitEulerIntegrator&>(sim->integrator());
    EXPECT_EQ(implicit.cholmod().analysisCount(), 1);
}
