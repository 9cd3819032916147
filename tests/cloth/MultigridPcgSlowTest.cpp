// Multigrid PCG on the bench's sheet at every bench resolution (129^2 takes seconds, so slow).
#include <gtest/gtest.h>

#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

TEST(MultigridPcgSlow, IterationsStayFlatFrom17To129OnTheBenchSheet) {
    // The bench's protocol (MultigridBench.cpp): 30 warm-up steps of 1/60 s, then the next steps'
    // iterations. Block-Jacobi PCG needs 64 / 174 / 423 / 864 here.
    double iterations[4];
    const int resolutions[4] = {17, 33, 65, 129};
    for (int r = 0; r < 4; ++r) {
        ClothMaterial material;
        material.damping = 0.01;
        SimulationSettings settings;
        settings.integrator = IntegratorKind::ImplicitMultigrid;
        auto sim = test::cornerPinnedSheet(test::horizontalSheet(uint32_t(resolutions[r] - 1)),
                                           material, settings);
        for (int i = 0; i < 30; ++i) ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
        int total = 0;
        for (int i = 0; i < 3; ++i) {
            ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
            total += sim->lastStats().iterations;
            EXPECT_TRUE(sim->lastStats().converged);
        }
        iterations[r] = total / 3.0;
    }
    EXPECT_LE(iterations[3], 2.0 * iterations[1])
        << iterations[0] << " " << iterations[1] << " " << iterations[2] << " " << iterations[3];
    for (double it : iterations) EXPECT_LE(it, 20.0);
}
