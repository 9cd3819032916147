// crowdcloth drape demo: a 1 m x 1 m sheet pinned at its two top corners falls and drapes, once per
// force model and integrator. Prints, per second of simulated time, the sag, the largest edge
// strain, the kinetic energy and the cost per step, then a summary table.
//
// Usage: cc_drape [resolution=32] [seconds=3]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/core/RectanglePanel.h"

using namespace cc;
using namespace cc::cloth;

namespace {

struct Outcome {
    double sag = 0, strain = 0, kinetic = 0, msPerStep = 0, iterations = 0, substeps = 0;
    bool ok = true;
    std::string error;
};

Outcome run(const char* label, ForceModelKind model, IntegratorKind integrator, double damping, uint32_t resolution,
            double seconds) {
    RectanglePanel panel;
    panel.columns = panel.rows = resolution;
    panel.origin = Vec3(-0.5, 1.0, 0.0);
    panel.vAxis = Vec3(0.0, 0.0, 1.0);  // lies flat (horizontal) at 1 m, then falls
    const ClothMesh mesh = panel.build().value();

    ClothMaterial material;   // defaults: 0.15 kg/m^2, 5e3 N/m stretch, 5e2 N/m shear, 1e-5 N m bend
    material.damping = damping;  // [s] Rayleigh
    SimulationSettings settings;
    settings.forceModel = model;
    settings.integrator = integrator;
    settings.strainLimit = 0.1;
    auto created = ClothSimulation::create(mesh, material, settings);
    Outcome out;
    if (!created.isOk()) {
        out.ok = false;
        out.error = created.status().message();
        return out;
    }
    ClothSimulation& sim = *created.value();
    const uint32_t cornerA = panel.vertexIndex(0, resolution), cornerB = panel.vertexIndex(resolution, resolution);
    (void)sim.constraints().pin(cornerA, mesh.positions[cornerA]);
    (void)sim.constraints().pin(cornerB, mesh.positions[cornerB]);

    const double dt = 1.0 / 60.0;
    const int steps = static_cast<int>(std::lround(seconds / dt)); // seconds > 0 (main checks)
    double totalIterations = 0, totalSubsteps = 0, totalMs = 0;
    std::printf("\n%s, %u x %u squares (%u vertices)\n", label, resolution, resolution, sim.state().vertexCount());
    std::printf("  %6s %9s %10s %12s %10s\n", "t [s]", "sag [m]", "strain [%]", "kinetic [J]", "ms/step");
    for (int s = 1; s <= steps; ++s) {
        const auto t0 = std::chrono::steady_clock::now();
        const Status status = sim.step(dt);
        const auto t1 = std::chrono::steady_clock::now();
        if (!status) {
            out.ok = false;
            out.error = status.message();
            std::printf("  step %d failed: %s\n", s, status.message().c_str());
            return out;
        }
        totalMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
        totalIterations += sim.lastStats().iterations;
        totalSubsteps += sim.lastStats().substeps;
        if (s % 60 == 0 || s == steps) {
            double lowest = 1e30;
            for (const Vec3& p : sim.state().positions) lowest = std::min(lowest, p.y());
            std::printf("  %6.2f %9.4f %10.2f %12.3e %10.3f\n", s * dt, 1.0 - lowest, 100.0 * sim.maxEdgeStrain(),
                        sim.state().kineticEnergy(), totalMs / s);
        }
    }
    double lowest = 1e30;
    for (const Vec3& p : sim.state().positions) lowest = std::min(lowest, p.y());
    out.sag = 1.0 - lowest;
    out.strain = sim.maxEdgeStrain();
    out.kinetic = sim.state().kineticEnergy();
    out.msPerStep = totalMs / steps;
    out.iterations = totalIterations / steps;
    out.substeps = totalSubsteps / steps;
    return out;
}

} // namespace

int main(int argc, char** argv) {
    const uint32_t resolution = argc > 1 ? static_cast<uint32_t>(std::atoi(argv[1])) : 32;
    const double seconds = argc > 2 ? std::atof(argv[2]) : 3.0;
    if (resolution < 2 || resolution > 512 || !(seconds > 0.0 && seconds <= 600.0)) {
        std::fprintf(stderr, "usage: cc_drape [resolution 2..512] [seconds (0, 600]]\n");
        return 2;
    }
    std::printf("crowdcloth drape: sheet pinned at two corners, 60 Hz steps, strain limit 10%%\n");
    struct Case {
        const char* label;
        ForceModelKind model;
        IntegratorKind integrator;
        double damping;  // [s] Rayleigh; explicit runs undamped: beta K v is itself a stiff term
                         // (0.01 s would need ~13k substeps per 60 Hz step)
    };
    const Case cases[] = {
        {"continuum (Baraff-Witkin) + implicit Euler / PCG", ForceModelKind::Continuum, IntegratorKind::ImplicitPcg, 0.01},
        {"continuum (Baraff-Witkin) + implicit Euler / CHOLMOD", ForceModelKind::Continuum, IntegratorKind::ImplicitCholmod, 0.01},
        {"mass-spring (Provot) + implicit Euler / PCG", ForceModelKind::MassSpring, IntegratorKind::ImplicitPcg, 0.01},
        {"mass-spring (Provot) + symplectic Euler, undamped", ForceModelKind::MassSpring, IntegratorKind::SymplecticEuler, 0.0},
    };
    Outcome outcomes[4];
    for (int i = 0; i < 4; ++i) {
        outcomes[i] = run(cases[i].label, cases[i].model, cases[i].integrator, cases[i].damping, resolution, seconds);
    }

    std::printf("\nSummary after %.1f s (%u x %u squares):\n", seconds, resolution, resolution);
    std::printf("  %-52s %8s %10s %11s %9s %10s %9s\n", "setup", "sag [m]", "strain [%]", "kinetic [J]", "ms/step",
                "CG iters", "substeps");
    int failures = 0;
    for (int i = 0; i < 4; ++i) {
        const Outcome& o = outcomes[i];
        if (!o.ok) {
            std::printf("  %-52s FAILED: %s\n", cases[i].label, o.error.c_str());
            ++failures;
            continue;
        }
        std::printf("  %-52s %8.4f %10.2f %11.2e %9.3f %10.1f %9.1f\n", cases[i].label, o.sag, 100.0 * o.strain,
                    o.kinetic, o.msPerStep, o.iterations, o.substeps);
    }
    return failures == 0 ? 0 : 1;
}
