// Rayleigh stiffness damping in the substepped Newton solver (SubstepSettings::stiffnessDamping):
// the damped oscillator's closed-form decay, no effect on a translation or on the statics.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "crowdcloth/cloth/ClothTopology.h"
#include "crowdcloth/cloth/SubstepSimulation.h"
#include "support/SheetScenes.h"
#include "support/SpringChain.h"

using namespace cc;
using namespace cc::cloth;

namespace {

constexpr double kStandardGravity = 9.81;

// The oscillation's energy about the equilibrium, averaged over `steps` steps of dt.
double meanOscillationEnergy(SubstepSimulation& sim, const SubstepSettings& settings, double dt, int steps,
                             double mass, double k, double equilibriumY) {
    double sum = 0.0;
    for (int s = 0; s < steps; ++s) {
        EXPECT_TRUE(sim.step(dt, settings).isOk());
        const double offset = sim.positions()[1].y() - equilibriumY;
        sum += 0.5 * k * offset * offset + 0.5 * mass * sim.velocities()[1].squaredNorm();
    }
    return sum / steps;
}

} // namespace

TEST(StiffnessDamping, AnOscillationDecaysAtTheClosedFormRate) {
    // m x'' = -k x - beta k x': for light damping the energy decays as exp(-beta k t / m) (averaged
    // over a period). m = 10 g, k = 1 N/m (omega = 10 rad/s), beta = 0.02 s: 2 per second. With 64
    // substeps of a 60 Hz step backward Euler's own damping (omega^2 h / 2 in the amplitude) is
    // 0.013 per second in the energy, which the undamped run measures and the check removes.
    const double mass = 0.01, k = 1.0, rest = 0.1, beta = 0.02, dt = 1.0 / 60.0;
    const double equilibriumY = -rest - mass * kStandardGravity / k;
    const int period = int(std::lround(2.0 * M_PI / std::sqrt(k / mass) / dt));  // 38 steps, ~0.63 s
    const int gap = 2 * period;                                                  // ~1.26 s
    double rates[2];
    for (int damped = 0; damped < 2; ++damped) {
        auto sim = test::hangingChain(1, mass, k, rest);
        sim->positions()[1].y() = equilibriumY - 0.02;
        SubstepSettings settings;
        settings.substeps = 64;
        settings.stiffnessDamping = damped ? beta : 0.0;
        const double first = meanOscillationEnergy(*sim, settings, dt, period, mass, k, equilibriumY);
        meanOscillationEnergy(*sim, settings, dt, gap - period, mass, k, equilibriumY);
        const double later = meanOscillationEnergy(*sim, settings, dt, period, mass, k, equilibriumY);
        rates[damped] = -std::log(later / first) / (gap * dt);
    }
    EXPECT_LT(rates[0], 0.05) << "backward Euler's own damping at this substep";
    EXPECT_NEAR(rates[1] - rates[0], beta * k / mass, 0.05 * beta * k / mass);
}

TEST(StiffnessDamping, LeavesAThrownSheetsFallAlone) {
    // A translation is in K's null space: a free sheet thrown sideways falls exactly as without
    // damping, roundoff aside.
    const ClothMesh mesh = test::verticalSheet(8).build().value();
    std::vector<Vec3> thrown[2];
    for (int damped = 0; damped < 2; ++damped) {
        SubstepSettings settings;
        settings.stiffnessDamping = damped ? 0.05 : 0.0;
        auto sheet = SubstepSimulation::create(mesh, ClothMaterial{}, {}).value();
        for (Vec3& v : sheet->velocities()) v = Vec3(1.0, 2.0, 0.5);
        for (int step = 0; step < 60; ++step) ASSERT_TRUE(sheet->step(1.0 / 60.0, settings).isOk());
        thrown[damped] = sheet->positions();
    }
    double apart = 0.0;
    for (std::size_t v = 0; v < thrown[0].size(); ++v) apart = std::max(apart, (thrown[1][v] - thrown[0][v]).norm());
    EXPECT_LT(apart, 1e-12);
}

TEST(StiffnessDamping, AHangingChainReachesTheSameExactExtensions) {
    // Damping acts on motion only: at rest spring j of an N-mass chain (from the top, 1-based)
    // carries the N - j + 1 masses below it, as without (SubstepSolver.HangingChain...).
    const int n = 8;
    const double mass = 0.01, k = 50.0, rest = 0.05;
    auto sim = test::hangingChain(n, mass, k, rest);
    SubstepSettings settings;
    settings.substeps = 1;
    settings.stiffnessDamping = 0.05;
    // The damped system differs from the preconditioner (the undamped springs' Laplacian), so a
    // truncated CG would settle where its own error balances: converge it, and the damping's terms
    // cancel at rest.
    settings.iterations = 40;
    for (int step = 0; step < 1000; ++step) ASSERT_TRUE(sim->step(1.0 / 20.0, settings).isOk());
    for (int j = 1; j <= n; ++j) {
        const double length = (sim->positions()[j - 1] - sim->positions()[j]).norm();
        EXPECT_NEAR(length - rest, (n - j + 1) * mass * kStandardGravity / k, 1e-9) << "spring " << j;
    }
}

TEST(StiffnessDamping, OutOfRangeIsRefusedByName) {
    auto sim = test::hangingChain(1, 0.01, 1.0, 0.1);
    for (double bad : {-0.001, 10.5, std::numeric_limits<double>::quiet_NaN()}) {
        SubstepSettings settings;
        settings.stiffnessDamping = bad;
        const Status s = sim->step(1.0 / 60.0, settings);
        ASSERT_FALSE(s.isOk()) << bad;
        EXPECT_NE(s.message().find("stiffnessDamping"), std::string::npos) << s.message();
    }
}
