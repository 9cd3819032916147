// Closed-form checks of the integrators (TESTPLAN A1, A2, B1).
#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/cloth/MassSpringModel.h"
#include "support/SheetScenes.h"

using namespace cc;
using namespace cc::cloth;

using test::kAllIntegrators;

namespace {

SimulationSettings settingsFor(IntegratorKind kind) {
    SimulationSettings s;
    s.integrator = kind;
    s.implicit.pcg.relativeTolerance = 1e-12;
    return s;
}

// Vertex 0 pinned at the origin, vertex 1 hanging below it on a spring of stiffness k, rest length
// `rest`, moving along the (vertical) spring axis, where the force is exactly linear.
std::unique_ptr<ClothSimulation> oscillator(IntegratorKind kind, double k, double mass, double rest, double offset) {
    auto model = MassSpringModel::fromSprings(2, {{0, 1, k, rest, SpringKind::Structural}});
    SimulationSettings s = settingsFor(kind);
    s.gravity = Vec3::Zero();
    s.explicitEuler.fixedSubsteps = 1;
    auto sim = ClothSimulation::create(std::move(model.value()), {Vec3::Zero(), Vec3(0, -(rest + offset), 0)},
                                       {1.0, mass}, 0.0, s);
    EXPECT_TRUE(sim.isOk()) << sim.status().message();
    (void)sim.value()->constraints().pin(0, Vec3::Zero());
    return std::move(sim).value();
}

} // namespace

TEST(FreeFall, EveryIntegratorMatchesTheDiscreteClosedForm) {
    // Symplectic and linearised backward Euler both give v_n = v0 + n h g, x_n = x0 + n h v0 +
    // h^2 g n(n+1)/2, i.e. x0 + v0 t + g t^2/2 + g h t/2 with t = n h.
    const Vec3 g(0.0, -9.81, 0.0), x0(1.0, 2.0, 3.0), v0(0.5, 4.0, -1.0);
    const double h = 1.0 / 60.0;
    const int n = 120;
    for (IntegratorKind kind : kAllIntegrators) {
        auto model = MassSpringModel::fromSprings(1, {});
        auto sim = ClothSimulation::create(std::move(model.value()), {x0}, {0.3}, 0.0, settingsFor(kind)).value();
        sim->state().velocities[0] = v0;
        for (int i = 0; i < n; ++i) ASSERT_TRUE(sim->step(h).isOk());
        const double t = n * h;
        const Vec3 expected = x0 + v0 * t + 0.5 * g * t * t + 0.5 * g * h * t;
        EXPECT_LT((sim->state().positions[0] - expected).norm(), 1e-12 * expected.norm()) << sim->integrator().name();
        EXPECT_LT((sim->state().velocities[0] - (v0 + g * t)).norm(), 1e-12 * 10) << sim->integrator().name();
    }
}

TEST(Oscillator, BackwardEulerAmplitudeShrinksByOneOverSqrtOnePlusOmegaHSquared) {
    // Linear oscillator: the energy norm sqrt(u^2 + (v/omega)^2) shrinks by exactly
    // 1/sqrt(1 + (omega h)^2) per backward Euler step.
    const double k = 400.0, m = 0.25, omega = std::sqrt(k / m);
    for (IntegratorKind kind : {IntegratorKind::ImplicitPcg, IntegratorKind::ImplicitCholmod}) {
        for (double omegaH : {0.1, 1.0, 2.0}) {
            auto sim = oscillator(kind, k, m, 1.0, 0.2);
            const double h = omegaH / omega;
            auto amplitude = [&] {
                const double u = -sim->state().positions[1].y() - 1.0;
                const double v = sim->state().velocities[1].y();
                return std::sqrt(u * u + v * v / (omega * omega));
            };
            double previous = amplitude();
            for (int i = 0; i < 10; ++i) {
                ASSERT_TRUE(sim->step(h).isOk());
                const double now = amplitude();
                EXPECT_NEAR(now / previous, 1.0 / std::sqrt(1.0 + omegaH * omegaH), 1e-9)
                    << sim->integrator().name() << " omega h = " << omegaH << " step " << i;
                previous = now;
            }
        }
    }
}

TEST(Oscillator, SymplecticEulerIsBoundedBelowOmegaHTwoAndDivergesAbove) {
    const double k = 400.0, m = 0.25, omega = std::sqrt(k / m);
    auto maxAmplitude = [&](double omegaH) {
        auto sim = oscillator(IntegratorKind::SymplecticEuler, k, m, 1.0, 0.01);
        double worst = 0.0;
        for (int i = 0; i < 400; ++i) {
            EXPECT_TRUE(sim->step(omegaH / omega).isOk());
            worst = std::max(worst, std::abs(-sim->state().positions[1].y() - 1.0));
        }
        return worst;
    };
    EXPECT_LT(maxAmplitude(1.9), 0.01 * 10.0);  // bounded (oscillates within a constant factor)
    EXPECT_GT(maxAmplitude(2.1), 0.01 * 1e6);   // grows geometrically
}

TEST(Oscillator, SymplecticEulerGuardPicksSubstepsBelowTheLimit) {
    // With the stability estimate on, a step of omega h = 20 is split into enough substeps.
    const double k = 400.0, m = 0.25, omega = std::sqrt(k / m);
    auto model = MassSpringModel::fromSprings(2, {{0, 1, k, 1.0, SpringKind::Structural}});
    SimulationSettings s;
    s.integrator = IntegratorKind::SymplecticEuler;
    s.gravity = Vec3::Zero();
    auto sim = ClothSimulation::create(std::move(model.value()), {Vec3::Zero(), Vec3(0, -1.01, 0)}, {1e9, m}, 0.0, s).value();
    (void)sim->constraints().pin(0, Vec3::Zero());
    for (int i = 0; i < 50; ++i) {
        const Status status = sim->step(20.0 / omega);
        ASSERT_TRUE(status.isOk()) << status.message();
    }
    const int substeps = sim->lastStats().substeps;
    EXPECT_GE(substeps, 10);  // omega h per substep < 2
    EXPECT_LE(substeps, 30);  // and not absurdly many (Gershgorin overestimates by sqrt(2) here)
    EXPECT_LT(std::abs(sim->state().positions[1].y() + 1.0), 0.02);
}

TEST(Oscillator, SymplecticEulerRefusesWhenSubstepsExceedTheCap) {
    auto model = MassSpringModel::fromSprings(2, {{0, 1, 1e7, 0.01, SpringKind::Structural}});
    SimulationSettings s;
    s.integrator = IntegratorKind::SymplecticEuler;
    s.explicitEuler.maxSubsteps = 100;
    auto sim = ClothSimulation::create(std::move(model.value()), {Vec3::Zero(), Vec3(0, -0.01, 0)}, {1.0, 1e-6}, 0.0, s).value();
    const uint64_t before = sim->stateHash();
    const Status status = sim->step(1.0 / 15.0);
    ASSERT_FALSE(status.isOk());
    EXPECT_EQ(status.code(), StatusCode::InvalidArgument);
    EXPECT_NE(status.message().find("substeps"), std::string::npos) << status.message();
    EXPECT_NE(status.message().find("implicit"), std::string::npos) << status.message();
    EXPECT_EQ(sim->stateHash(), before);  // nothing was half-done
}

TEST(HangingChain, ImplicitSolversReachTheExactDiscreteExtensions) {
    // N masses hang below a pinned top vertex; spring j (counted from the top, 1-based) carries the
    // weight of the N - j + 1 masses below it, so it stretches by (N - j + 1) m g / k.
    const int n = 10;
    const double k = 50.0, m = 0.02, g = 9.81, rest = 0.1;
    for (IntegratorKind kind : {IntegratorKind::ImplicitPcg, IntegratorKind::ImplicitCholmod}) {
        std::vector<Spring> springs;
        std::vector<Vec3> x;
        std::vector<double> masses;
        for (int i = 0; i <= n; ++i) {
            x.push_back(Vec3(0, -rest * i, 0));
            masses.push_back(m);
            if (i > 0) springs.push_back({uint32_t(i - 1), uint32_t(i), k, rest, SpringKind::Structural});
        }
        SimulationSettings s = settingsFor(kind);
        auto sim = ClothSimulation::create(std::move(MassSpringModel::fromSprings(n + 1, springs).value()), x, masses,
                                           0.05, s).value();
        (void)sim->constraints().pin(0, Vec3::Zero());
        for (int i = 0; i < 400; ++i) ASSERT_TRUE(sim->step(0.05).isOk());
        for (int j = 1; j <= n; ++j) {
            const double length = (sim->state().positions[j] - sim->state().positions[j - 1]).norm();
            const double expected = rest + (n - j + 1) * m * g / k;
            EXPECT_NEAR(length, expected, 1e-6 * expected) << sim->integrator().name() << " spring " << j;
        }
    }
}
