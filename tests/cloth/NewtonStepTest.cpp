// Newton to convergence of the backward Euler step (ImplicitEulerIntegrator::Settings::
// newtonIterations): the step satisfies the nonlinear equations, checked independently of the
// integrator with a separately built force model.
#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/cloth/ClothTopology.h"
#include "crowdcloth/cloth/ContinuumModel.h"
#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

namespace {

constexpr double kDt = 1.0 / 30.0;

struct Residuals {
    double newton = 0.0;     // |S r(dv)| of the step taken, relative to |S r(-v0)|
    double reference = 0.0;  // |S r(-v0)|
};

// r(dv) = h (f(x1) + M g - beta K0 v1) - M dv on the free directions (all but the two pinned
// corners), K0 the definite stiffness at x0, for the step from `before` to `after` of the sheet.
Residuals backwardEulerResidual(const RectanglePanel& panel, const ClothMaterial& material,
                                const ClothState& before, const ClothState& after, const Vec3& g) {
    const ClothMesh mesh = panel.build().value();
    auto model =
        ContinuumModel::fromMesh(mesh, ClothTopology::build(mesh).value(), material).value();
    std::vector<std::pair<uint32_t, uint32_t>> couplings;
    model->appendCouplings(couplings);
    BlockSparseMatrix k0;
    k0.buildPattern(model->vertexCount(), couplings);
    model->bindMatrix(k0);
    const uint32_t n = before.vertexCount();
    std::vector<Vec3> f0(n, Vec3::Zero()), f1(n, Vec3::Zero()), k0v1(n);
    ForceEvaluation eval;
    eval.positions = before.positions;
    eval.outForces = f0;
    eval.outStiffness = &k0;
    model->evaluate(eval);
    ForceEvaluation eval1;
    eval1.positions = after.positions;
    eval1.outForces = f1;
    model->evaluate(eval1);
    k0.multiply(after.velocities, k0v1, {});

    Residuals out;
    double newton2 = 0.0, reference2 = 0.0;
    const uint32_t pins[] = {panel.vertexIndex(0, panel.rows),
                             panel.vertexIndex(panel.columns, panel.rows)};
    for (uint32_t i = 0; i < n; ++i) {
        const double m = before.masses[i];
        if (i == pins[0] || i == pins[1]) continue;  // S = 0
        const Vec3 dv = after.velocities[i] - before.velocities[i];
        newton2 += (kDt * (f1[i] + m * g - material.damping * k0v1[i]) - m * dv).squaredNorm();
        reference2 += (kDt * (f0[i] + m * g) + m * before.velocities[i]).squaredNorm();
    }
    out.reference = std::sqrt(reference2);
    out.newton = std::sqrt(newton2) / out.reference;
    return out;
}

struct NewtonScene {
    RectanglePanel panel = test::horizontalSheet(12);
    ClothMaterial material;
    std::unique_ptr<ClothSimulation> source;

    NewtonScene() {
        material.damping = 0.01;
        source = test::cornerPinnedSheet(panel, material, SimulationSettings{});
        for (int i = 0; i < 15; ++i) EXPECT_TRUE(source->step(kDt).isOk());
    }

    // One step from the source state with `settings`; returns the simulation after it.
    std::unique_ptr<ClothSimulation> step(SimulationSettings settings) const {
        settings.implicit.maxHalvings = 0;  // one step, not split: the equations are of this step
        auto sim = test::cornerPinnedSheet(panel, material, settings);
        sim->state() = source->state();
        EXPECT_TRUE(sim->step(kDt).isOk());
        return sim;
    }
};

} // namespace

TEST(NewtonStep, ConvergedStepSatisfiesTheNonlinearBackwardEulerEquations) {
    const NewtonScene setup;
    for (IntegratorKind integrator :
         {IntegratorKind::ImplicitCholmod, IntegratorKind::ImplicitMultigrid}) {
        SimulationSettings settings;
        settings.integrator = integrator;
        settings.implicit.newtonIterations = 60;
        settings.implicit.newtonTolerance = 1e-8;
        settings.implicit.pcg.relativeTolerance = 1e-10;
        const auto sim = setup.step(settings);
        const NewtonStats& stats =
            static_cast<const ImplicitEulerIntegrator&>(sim->integrator()).newtonStats();
        EXPECT_TRUE(stats.converged)
            << stats.iterations << " iterations, residual " << stats.relativeResidual;
        EXPECT_GT(stats.iterations, 2);
        const Residuals r =
            backwardEulerResidual(setup.panel, setup.material, setup.source->state(), sim->state(),
                                  sim->settings().gravity);
        EXPECT_LE(r.newton, 1e-8) << integratorKindName(integrator);
        // The integrator's own measure agrees with the independent one.
        EXPECT_NEAR(r.newton, stats.relativeResidual, 1e-10);
        // And the position update is backward Euler's x1 = x0 + h v1.
        for (uint32_t i = 0; i < sim->state().vertexCount(); ++i) {
            const Vec3 x1 = setup.source->state().positions[i] + kDt * sim->state().velocities[i];
            EXPECT_LT((sim->state().positions[i] - x1).norm(), 1e-14) << i;
        }
    }
}

TEST(NewtonStep, OneIterationIsTheLinearisedStepAndLeavesAResidual) {
    const NewtonScene setup;
    SimulationSettings linearised;
    linearised.integrator = IntegratorKind::ImplicitCholmod;
    SimulationSettings one = linearised;
    one.implicit.newtonIterations = 1;
    one.implicit.newtonTolerance = 1e-12;  // ignored with a single iteration
    const auto a = setup.step(linearised);
    const auto b = setup.step(one);
    EXPECT_EQ(a->stateHash(), b->stateHash());
    // The linearised step is off the nonlinear equations by much more than Newton's tolerance:
    // the test above is not trivially satisfied.
    const Residuals r = backwardEulerResidual(setup.panel, setup.material, setup.source->state(),
                                              a->state(), a->settings().gravity);
    EXPECT_GT(r.newton, 1e-4);
}

TEST(NewtonStep, StiffLargeStepConvergesWithTheLineSearch) {
    // 100x the default stretch stiffness at dt = 1/15 s from the flat sheet: full Newton steps
    // from the linearised one overshoot, and the Armijo backtracking (which keeps every iterate
    // decreasing the incremental potential) is what lets Newton converge.
    RectanglePanel panel = test::horizontalSheet(8);
    ClothMaterial material;
    material.stretchStiffness = 5.0e5;
    material.damping = 0.001;
    SimulationSettings settings;
    settings.integrator = IntegratorKind::ImplicitCholmod;
    settings.implicit.newtonIterations = 200;
    settings.implicit.newtonTolerance = 1e-6;
    settings.implicit.maxHalvings = 0;
    auto sim = test::cornerPinnedSheet(panel, material, settings);
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(sim->step(1.0 / 15.0).isOk());
        const NewtonStats& stats =
            static_cast<const ImplicitEulerIntegrator&>(sim->integrator()).newtonStats();
        EXPECT_TRUE(stats.converged) << "step " << i << ": " << stats.iterations
                                     << " iterations, residual " << stats.relativeResidual;
        if (i == 0) {
            EXPECT_GT(stats.backtracks, 0);
        }
    }
    EXPECT_LT(sim->maxEdgeStrain(), 0.05);
}

TEST(NewtonStep, BadSettingsAreRejectedByName) {
    const ClothMesh mesh = test::horizontalSheet(4).build().value();
    SimulationSettings s;
    s.implicit.newtonIterations = 0;
    auto sim = ClothSimulation::create(mesh, ClothMaterial{}, s);
    ASSERT_FALSE(sim.isOk());
    EXPECT_NE(sim.status().message().find("SimulationSettings.implicit.newtonIterations = 0"),
              std::string::npos);
    s = SimulationSettings{};
    s.implicit.newtonTolerance = 1.0;
    sim = ClothSimulation::create(mesh, ClothMaterial{}, s);
    ASSERT_FALSE(sim.isOk());
    EXPECT_NE(sim.status().message().find("SimulationSettings.implicit.newtonTolerance"),
              std::string::npos);
}
