// Pins, moving targets, contact planes and Provot strain limiting.
#include <gtest/gtest.h>

#include <cmath>

#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

using test::kAllIntegrators;

namespace {
SimulationSettings settingsFor(IntegratorKind kind) {
    SimulationSettings s;
    s.forceModel = ForceModelKind::MassSpring;
    s.integrator = kind;
    return s;
}

ClothMaterial softMaterial() {
    ClothMaterial m;
    m.stretchStiffness = 50.0;  // soft enough for explicit steps at 60 Hz
    m.shearStiffness = 10.0;
    return m;
}
} // namespace

TEST(Constraints, DrivenVertexFollowsAMovingTargetExactly) {
    for (IntegratorKind kind : kAllIntegrators) {
        RectanglePanel panel = test::verticalSheet(6);
        const ClothMesh mesh = panel.build().value();
        auto sim = ClothSimulation::create(mesh, softMaterial(), settingsFor(kind)).value();
        const uint32_t driven = panel.vertexIndex(3, 6);
        for (int i = 1; i <= 120; ++i) {
            const double t = i / 60.0;
            const Vec3 goal = mesh.positions[driven] + Vec3(0.3 * std::sin(4 * t), 0.1 * t, 0.2 * std::cos(3 * t) - 0.2);
            ASSERT_TRUE(sim->constraints().setTarget(driven, goal).isOk());
            const Status s = sim->step(1.0 / 60.0);
            ASSERT_TRUE(s.isOk()) << s.message();
            EXPECT_LT((sim->state().positions[driven] - goal).norm(), 1e-12) << sim->integrator().name() << " step " << i;
        }
        // Released, it falls with the rest of the sheet.
        const double heldAt = sim->state().positions[driven].y();
        sim->constraints().release(driven);
        for (int i = 0; i < 10; ++i) ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
        EXPECT_LT(sim->state().positions[driven].y(), heldAt - 0.05) << sim->integrator().name();
    }
}

TEST(Constraints, ContactPlanesStopTheSheetAndLetItSlide) {
    // A tilted sheet falls onto the floor y = 0. Vertices get a contact plane once they are within
    // 5 cm of it (what collision/ will hand in); none may end deeper than gravity carries a free
    // vertex within one step, none may hover, and the sheet keeps sliding sideways (no friction).
    for (IntegratorKind kind : kAllIntegrators) {
        RectanglePanel panel = test::horizontalSheet(8);
        panel.origin = Vec3(-0.5, 0.3, 0.0);
        panel.vAxis = Vec3(0.0, 0.2, 1.0).normalized();
        const ClothMesh mesh = panel.build().value();
        auto sim = ClothSimulation::create(mesh, softMaterial(), settingsFor(kind)).value();
        sim->state().velocities.assign(mesh.vertexCount(), Vec3(1.0, 0.0, 0.0));
        double lowest = 1.0;
        for (int i = 0; i < 120; ++i) {
            sim->constraints().clearContactPlanes();
            for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
                if (sim->state().positions[v].y() < 0.05) {
                    ASSERT_TRUE(sim->constraints().setContactPlane(v, Vec3::Zero(), Vec3::UnitY()).isOk());
                }
            }
            ASSERT_TRUE(sim->step(1.0 / 60.0).isOk());
            lowest = std::min(lowest, test::lowestY(sim->state()));
        }
        EXPECT_GT(lowest, -1.05 * 9.81 / (60.0 * 60.0)) << sim->integrator().name();  // h^2 g within a step
        EXPECT_LT(test::lowestY(sim->state()), 0.001) << sim->integrator().name();  // it landed
        EXPECT_GT(sim->state().positions[0].x(), -0.5 + 0.5) << sim->integrator().name();  // and slid (no friction yet)
    }
}

TEST(StrainLimit, ProvotTwoCornerHangStaysWithinTheLimit) {
    // Provot's test: a soft sheet hung by two corners. Without limiting its corners over-stretch;
    // with a 10% limit no edge exceeds it after any step.
    ClothMaterial material = softMaterial();
    material.stretchStiffness = 5.0;
    material.shearStiffness = 1.0;
    SimulationSettings settings = settingsFor(IntegratorKind::ImplicitPcg);
    auto unlimited = test::cornerPinnedSheet(test::horizontalSheet(10), material, settings);
    settings.strainLimit = 0.1;
    settings.strainLimitPasses = 200;  // Gauss-Seidel: 8 passes leave ~20%, 50 ~11%, 200 ~10.05%
    auto limited = test::cornerPinnedSheet(test::horizontalSheet(10), material, settings);
    double worstUnlimited = 0.0, worstLimited = 0.0;
    for (int i = 0; i < 180; ++i) {
        ASSERT_TRUE(unlimited->step(1.0 / 60.0).isOk());
        ASSERT_TRUE(limited->step(1.0 / 60.0).isOk());
        worstUnlimited = std::max(worstUnlimited, unlimited->maxEdgeStrain());
        worstLimited = std::max(worstLimited, limited->maxEdgeStrain());
    }
    RecordProperty("unlimited_max_strain", std::to_string(worstUnlimited));
    EXPECT_GT(worstUnlimited, 0.3);
    EXPECT_LE(worstLimited, 0.1 + 0.005);
}
