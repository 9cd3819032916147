#include "QualityReport.h"

#include "BenchScenes.h"
#include "BulletPeer.h"

#include <chrono>
#include <string>
#include <vector>

namespace cc::bench {

using cloth::IntegratorKind;

namespace {

struct QualityRow {
    std::string name;
    bool implicit = false;
    double strain = 0, sag = 0, msPerStep = 0, cgIterations = 0, substeps = 0;
    uint32_t vertexCount = 0;
    std::string error;  ///< empty when the run succeeded

    double vertexStepsPerSecond() const { return vertexCount / (1e-3 * msPerStep); }
};

using Clock = std::chrono::steady_clock;

double milliseconds(Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

QualityRow runOurs(const OurSetup& setup, int vertices) {
    QualityRow row;
    row.name = setupName(setup);
    row.implicit = setup.integrator != IntegratorKind::SymplecticEuler;
    auto created = createPatchSimulation(setup, vertices);
    if (!created.isOk()) {
        row.error = created.status().message();
        return row;
    }
    cloth::ClothSimulation& sim = *created.value();
    double totalMs = 0;
    for (int i = 0; i < kQualitySteps; ++i) {
        const auto start = Clock::now();
        const Status status = sim.step(kDt);
        totalMs += milliseconds(Clock::now() - start);
        if (!status) {
            row.error = "step " + std::to_string(i) + ": " + status.message();
            return row;
        }
        row.cgIterations += sim.lastStats().iterations;
        row.substeps += sim.lastStats().substeps;
    }
    row.vertexCount = sim.state().vertexCount();
    row.msPerStep = totalMs / kQualitySteps;
    row.cgIterations /= kQualitySteps;
    row.substeps /= kQualitySteps;
    row.strain = sim.maxEdgeStrain();
    row.sag = kPatchHeight - lowestY(sim.state().positions);
    return row;
}

QualityRow runBullet(int vertices, int positionIterations) {
    QualityRow row;
    row.name = positionIterations > 0 ? "Bullet piterations=" + std::to_string(positionIterations)
                                      : "Bullet btSoftBody";
    BulletPatch patch(vertices, positionIterations);
    double totalMs = 0;
    for (int i = 0; i < kQualitySteps; ++i) {
        const auto start = Clock::now();
        const int internalSteps = patch.step();
        totalMs += milliseconds(Clock::now() - start);
        if (internalSteps != 1) {
            row.error = "Bullet took " + std::to_string(internalSteps) + " internal steps";
            return row;
        }
    }
    row.vertexCount = static_cast<uint32_t>(patch.vertexCount());
    row.msPerStep = totalMs / kQualitySteps;
    row.strain = patch.maxEdgeStrain();
    row.sag = kPatchHeight - patch.lowestY();
    return row;
}

void printRow(std::FILE* out, int vertices, const QualityRow& row, const QualityRow& bullet) {
    if (!row.error.empty()) {
        std::fprintf(out, "  %-30s %4d  FAILED: %s\n", row.name.c_str(), vertices,
                     row.error.c_str());
        return;
    }
    std::fprintf(out, "  %-30s %4d %9.2f %8.3f %9.3f %10.3f %9.3f", row.name.c_str(), vertices,
                 100.0 * row.strain, row.sag, row.msPerStep, 1e-6 * row.vertexStepsPerSecond(),
                 row.vertexStepsPerSecond() / bullet.vertexStepsPerSecond());
    if (row.cgIterations > 0) std::fprintf(out, "   cg %.1f", row.cgIterations);
    if (row.substeps > 1) std::fprintf(out, "   substeps %.2f", row.substeps);
    std::fprintf(out, "\n");
    std::fflush(out);
}

std::vector<OurSetup> qualitySetups(bool full) {
    using cloth::ForceModelKind;
    if (!full) {
        return {{ForceModelKind::MassSpring, IntegratorKind::ImplicitPcg, 0},
                {ForceModelKind::Continuum, IntegratorKind::ImplicitPcg, 0}};
    }
    std::vector<OurSetup> setups = allOurSetups();
    // Bullet runs on one thread: single-threaded PCG rows make the per-core comparison explicit.
    for (ForceModelKind model : {ForceModelKind::MassSpring, ForceModelKind::Continuum}) {
        setups.push_back({model, IntegratorKind::ImplicitPcg, 1});
    }
    return setups;
}

} // namespace

bool runQualityReport(std::FILE* out, bool full) {
    std::fprintf(out, "\nQuality after %.0f s (%d steps from rest).\n", kQualitySteps * kDt,
                 kQualitySteps);
    std::fprintf(out,
                 "  strain    max over mesh edges of length / rest length - 1; for Bullet over\n"
                 "            all non-bending links (grid neighbours plus triangle diagonals)\n"
                 "  sag       1 m - lowest y\n"
                 "  ms/step   mean steady_clock time over all %d steps\n"
                 "  x Bullet  vertex-steps per second relative to Bullet's default config\n"
                 "            (first row of each size); Bullet runs on one thread, ours on all\n\n",
                 kQualitySteps);
    std::fprintf(out, "  %-30s %4s %9s %8s %9s %10s %9s\n", "setup", "N", "strain[%]", "sag[m]",
                 "ms/step", "Mvtx-st/s", "x Bullet");

    bool allOk = true;
    std::vector<std::string> verdicts;
    const std::vector<int> resolutions =
        full ? std::vector<int>{33, kBarResolution} : std::vector<int>{kBarResolution};
    for (int vertices : resolutions) {
        const QualityRow bullet = runBullet(vertices, 0);
        if (!bullet.error.empty()) {
            std::fprintf(out, "  Bullet %d^2 FAILED: %s\n", vertices, bullet.error.c_str());
            allOk = false;
            continue;
        }
        printRow(out, vertices, bullet, bullet);
        if (full) {
            // Bullet's default cloth stretches far more than ours; more position iterations show
            // what its step costs on the way to a comparable strain.
            for (int iterations : {10, 100}) {
                printRow(out, vertices, runBullet(vertices, iterations), bullet);
            }
        }
        for (const OurSetup& setup : qualitySetups(full)) {
            const QualityRow row = runOurs(setup, vertices);
            printRow(out, vertices, row, bullet);
            allOk = allOk && row.error.empty();
            if (vertices != kBarResolution || !row.implicit || !row.error.empty()) continue;
            const double speedup = row.vertexStepsPerSecond() / bullet.vertexStepsPerSecond();
            const bool fastEnough = speedup >= kBarSpeedup,
                       stiffEnough = row.strain <= bullet.strain;
            char verdict[256];
            std::snprintf(
                verdict, sizeof verdict,
                "  %-30s %-6s  speed %5.3fx Bullet (%s), max strain %.2f%% vs %.2f%% (%s)",
                row.name.c_str(), fastEnough && stiffEnough ? "MEETS" : "MISSES", speedup,
                fastEnough ? "ok" : "too slow", 100.0 * row.strain, 100.0 * bullet.strain,
                stiffEnough ? "ok" : "stretchier");
            verdicts.push_back(verdict);
        }
        std::fprintf(out, "\n");
    }

    std::fprintf(out,
                 "Bar at %d^2: an implicit step at >= %.0fx the vertex-steps/s of Bullet's\n"
                 "default config, with max strain <= Bullet's\n",
                 kBarResolution, kBarSpeedup);
    for (const std::string& verdict : verdicts) std::fprintf(out, "%s\n", verdict.c_str());
    std::fprintf(out, "\n");
    std::fflush(out);
    return allOk;
}

} // namespace cc::bench
