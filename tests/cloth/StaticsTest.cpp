// Statics: equilibria with known answers, convergence under refinement, independence of dt.
#include <gtest/gtest.h>

#include <cmath>

#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

// Runs until the kinetic energy stays below `tolerance` [J] (or `maxSteps`), returns steps taken.
int settle(ClothSimulation& sim, double dt, int maxSteps, double tolerance) {
    for (int i = 1; i <= maxSteps; ++i) {
        const Status s = sim.step(dt);
        EXPECT_TRUE(s.isOk()) << s.message();
        if (!s.isOk()) return i;
        if (i > 10 && sim.state().kineticEnergy() < tolerance) return i;
    }
    return maxSteps;
}

} // namespace

TEST(HangingSheet, ContinuumTopEdgePinnedConvergesToRhoGHSquaredOverTwoY) {
    // A sheet hung by its whole top edge carries, at height y, the weight of the cloth below it:
    // strain rho g y / Y, total extension rho g H^2 / (2 Y) for the Baraff-Witkin membrane (no
    // Poisson coupling). On the 4-8 mesh the lumped masses alternate (valence 4 and 8), so a row
    // is not exactly level and the discrete answer converges to the continuum one at second order.
    ClothMaterial material;
    material.stretchStiffness = 50.0;  // soft, so the 1.5 cm extension is large against roundoff
    material.damping = 0.05;
    const double expected = material.arealDensity * 9.81 * 1.0 / (2.0 * material.stretchStiffness);
    double previousError = 0.0;
    for (uint32_t squares : {4u, 8u, 16u}) {
        RectanglePanel panel = test::verticalSheet(squares);
        SimulationSettings settings;
        settings.implicit.pcg.relativeTolerance = 1e-10;
        const ClothMesh mesh = panel.build().value();
        auto sim = ClothSimulation::create(mesh, material, settings).value();
        for (uint32_t i = 0; i <= squares; ++i) {
            const uint32_t top = panel.vertexIndex(i, squares);
            ASSERT_TRUE(sim->constraints().pin(top, mesh.positions[top]).isOk());
        }
        settle(*sim, 0.1, 3000, 1e-18);
        const double error = std::abs(-test::lowestY(sim->state()) - expected);
        EXPECT_LT(error, 0.01 * expected) << squares << " squares";
        if (previousError > 0.0) {
            EXPECT_GT(previousError / error, 3.0) << squares << " squares: not second order";  // 3.4, 3.8 -> 4
        }
        previousError = error;
    }
    EXPECT_LT(previousError, 1e-3 * expected);
}

TEST(HangingSheet, CornerPinnedSheetComesToRest) {
    for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
        ClothMaterial material;
        material.damping = 0.02;
        SimulationSettings settings;
        settings.forceModel = model;
        auto sim = test::cornerPinnedSheet(test::horizontalSheet(12), material, settings);
        ASSERT_TRUE(sim);
        settle(*sim, 1.0 / 60.0, 1200, 0.0);
        EXPECT_LT(sim->state().kineticEnergy(), 1e-6) << "kinetic energy after 20 s, model " << int(model);
        EXPECT_GT(1.0 - test::lowestY(sim->state()), 0.9);  // it fell and hangs from the corners
        EXPECT_TRUE(sim->lastStats().converged);
    }
}

namespace {

// Sag (1 m minus the lowest point) of a corner-pinned sheet at rest. A modest stretch stiffness
// and a real bending stiffness give a smooth drape whose shape is set by stretch, gravity and
// bending rather than by buckling, so it has a resolution limit to converge to.
double restingSag(ForceModelKind model, uint32_t squares, double dt) {
    ClothMaterial material;
    material.stretchStiffness = 200.0;
    material.shearStiffness = 100.0;
    material.bendStiffness = 1e-3;
    material.damping = 0.02;
    SimulationSettings settings;
    settings.forceModel = model;
    settings.implicit.pcg.relativeTolerance = 1e-6;
    auto sim = test::cornerPinnedSheet(test::horizontalSheet(squares), material, settings);
    const int steps = static_cast<int>(std::ceil(25.0 / dt));
    settle(*sim, dt, steps, 1e-10);
    return 1.0 - test::lowestY(sim->state());
}

} // namespace

TEST(HangingSheet, SagConvergesUnderRefinement) {
    for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
        const double coarse = restingSag(model, 8, 1.0 / 30.0);
        const double middle = restingSag(model, 16, 1.0 / 30.0);
        const double fine = restingSag(model, 32, 1.0 / 30.0);
        RecordProperty(model == ForceModelKind::Continuum ? "continuum_sag" : "mass_spring_sag", std::to_string(fine));
        // Coarse vs two 4-8 levels finer (one halving of the grid spacing) within a few percent,
        // and the differences shrink as the mesh refines. (They shrink slowly: a point pin is a
        // stress singularity in a membrane, so the strain next to it grows as the mesh refines.)
        EXPECT_LT(std::abs(middle - fine) / fine, 0.03) << coarse << " " << middle << " " << fine;
        EXPECT_LT(std::abs(coarse - middle) / middle, 0.03) << coarse << " " << middle << " " << fine;
        EXPECT_LT(std::abs(middle - fine), std::abs(coarse - middle)) << coarse << " " << middle << " " << fine;
    }
}

TEST(HangingSheet, SagDoesNotDependOnTheStepSize) {
    for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
        const double reference = restingSag(model, 12, 1.0 / 240.0);
        for (double hz : {30.0, 60.0, 120.0}) {
            const double sag = restingSag(model, 12, 1.0 / hz);
            EXPECT_LT(std::abs(sag - reference) / reference, 0.02) << hz << " Hz: " << sag << " vs " << reference;
        }
    }
}
