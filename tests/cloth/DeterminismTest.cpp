// Same input -> bit-identical state, for any thread count (STYLE.md section 6).
#include <gtest/gtest.h>

#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

std::vector<uint64_t> hashes(ForceModelKind model, IntegratorKind integrator, int threads) {
    ClothMaterial material;
    material.damping = 0.01;
    SimulationSettings settings;
    settings.forceModel = model;
    settings.integrator = integrator;
    settings.strainLimit = 0.05;
    settings.parallel.maxThreads = threads;
    settings.parallel.minParallel = 1;  // exercise the parallel paths on a small garment
    if (integrator == IntegratorKind::SymplecticEuler) material.damping = 0.0;
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(20), material, settings);
    std::vector<uint64_t> out;
    for (int i = 0; i < 20; ++i) {
        const Status s = sim->step(1.0 / 60.0);
        EXPECT_TRUE(s.isOk()) << s.message();
        out.push_back(sim->stateHash());
    }
    return out;
}

} // namespace

TEST(Determinism, RepeatedRunsAreBitIdentical) {
    EXPECT_EQ(hashes(ForceModelKind::Continuum, IntegratorKind::ImplicitPcg, 2),
              hashes(ForceModelKind::Continuum, IntegratorKind::ImplicitPcg, 2));
}

TEST(Determinism, ThreadCountDoesNotChangeTheResult) {
    const struct {
        ForceModelKind model;
        IntegratorKind integrator;
    } cases[] = {{ForceModelKind::Continuum, IntegratorKind::ImplicitPcg},
                 {ForceModelKind::MassSpring, IntegratorKind::ImplicitPcg},
                 {ForceModelKind::Continuum, IntegratorKind::ImplicitCholmod},
                 {ForceModelKind::Continuum, IntegratorKind::ImplicitMultigrid},
                 {ForceModelKind::MassSpring, IntegratorKind::SymplecticEuler}};
    for (const auto& c : cases) {
        const auto serial = hashes(c.model, c.integrator, 1);
        for (int threads : {2, 3, 4}) {
            EXPECT_EQ(serial, hashes(c.model, c.integrator, threads))
                << "model " << int(c.model) << " integrator " << int(c.integrator) << " threads " << threads;
        }
    }
}
