#include "SolverFront.h"

#include "BenchScenes.h"
#include "BulletPeer.h"
#include "crowdcloth/cloth/SubstepSimulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

namespace cc::bench {

namespace {

using Clock = std::chrono::steady_clock;
using Trajectory = std::vector<std::vector<Vec3>>;

constexpr int kRunFrames = 180;    ///< 3 s: strain and sag over the whole run
constexpr int kErrorFrames = 30;   ///< 0.5 s after the flat release: the swing, before chaos
constexpr int kReferenceFine = 32; ///< reference substeps per frame (Richardson with half as many)
constexpr uint32_t kCacheVersion = 2;  ///< 2: Newton-converged reference

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// The front's model: Provot springs of the default material, no Rayleigh damping.
cloth::ClothMaterial frontMaterial() { return cloth::ClothMaterial{}; }

std::vector<uint32_t> pinnedCorners(const RectanglePanel& panel) {
    return {panel.vertexIndex(0, panel.rows), panel.vertexIndex(panel.columns, panel.rows)};
}

/// One configuration: how to make it and how to step it one frame.
struct Stepper {
    std::function<Status()> step;
    std::function<const std::vector<Vec3>&()> positions;
    std::function<double()> strain;
    std::function<int()> iterations;  ///< of the last frame
};

/// Backward Euler on the Provot springs through ClothSimulation: block-Jacobi PCG, one Newton
/// step (the baseline), or Newton to convergence with multigrid PCG (the reference).
struct ImplicitRun {
    std::unique_ptr<cloth::ClothSimulation> sim;
    int substeps = 1;
    bool converged = false;  ///< Newton to convergence, tight linear solves

    Result<Stepper> make(int vertices, double tolerance) {
        const RectanglePanel panel = patchPanel(vertices);
        auto mesh = panel.build();
        if (!mesh.isOk()) return mesh.status();
        cloth::SimulationSettings settings;
        settings.forceModel = cloth::ForceModelKind::MassSpring;
        settings.integrator = converged ? cloth::IntegratorKind::ImplicitMultigrid : cloth::IntegratorKind::ImplicitPcg;
        settings.gravity = Vec3(0.0, kGravity, 0.0);
        settings.parallel.maxThreads = 1;
        settings.implicit.pcg.relativeTolerance = tolerance;
        if (converged) {
            settings.implicit.newtonIterations = 20;
            settings.implicit.newtonTolerance = 1e-8;
        }
        settings.implicit.maxHalvings = substeps > 1 ? 0 : settings.implicit.maxHalvings;
        auto created = cloth::ClothSimulation::create(mesh.value(), frontMaterial(), settings);
        if (!created.isOk()) return created.status();
        sim = std::move(created).value();
        for (uint32_t corner : pinnedCorners(panel))
            if (Status s = sim->constraints().pin(corner, mesh.value().positions[corner]); !s) return s;
        Stepper stepper;
        stepper.step = [this]() -> Status {
            int iterations = 0;
            for (int s = 0; s < substeps; ++s) {
                if (Status st = sim->step(kDt / substeps); !st) return st;
                iterations += sim->lastStats().iterations;
            }
            lastIterations = iterations;
            return Status::ok();
        };
        stepper.positions = [this]() -> const std::vector<Vec3>& { return sim->state().positions; };
        stepper.strain = [this] { return sim->maxEdgeStrain(); };
        stepper.iterations = [this] { return lastIterations; };
        return stepper;
    }
    int lastIterations = 0;
};

/// The substepped local/global solver.
struct SubstepRun {
    std::unique_ptr<cloth::SubstepSimulation> sim;
    cloth::SubstepSettings settings;

    Result<Stepper> make(int vertices) {
        const RectanglePanel panel = patchPanel(vertices);
        auto mesh = panel.build();
        if (!mesh.isOk()) return mesh.status();
        auto created = cloth::SubstepSimulation::create(mesh.value(), frontMaterial(), pinnedCorners(panel));
        if (!created.isOk()) return created.status();
        sim = std::move(created).value();
        sim->setAcceleration(Vec3(0.0, kGravity, 0.0));
        Stepper stepper;
        stepper.step = [this] { return sim->step(kDt, settings); };
        stepper.positions = [this]() -> const std::vector<Vec3>& { return sim->positions(); };
        stepper.strain = [this] { return sim->maxEdgeStrain(); };
        stepper.iterations = [this] { return settings.substeps * settings.iterations; };
        return stepper;
    }
};

struct Row {
    std::string name;
    double ms = 0.0, iterations = 0.0, strain = 0.0, sag = 0.0;
    double errorMm = NAN;  ///< NaN when there is no reference at this resolution
    std::string failure;
};

double rmsMm(const Trajectory& a, const Trajectory& b) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t f = 0; f < a.size() && f < b.size(); ++f)
        for (std::size_t v = 0; v < a[f].size(); ++v, ++count) sum += (a[f][v] - b[f][v]).squaredNorm();
    return count ? 1000.0 * std::sqrt(sum / double(count)) : NAN;
}

/// Runs a configuration for kRunFrames; the first kErrorFrames are compared with `reference`. The
/// first frame (factorisations, first-touch allocation) is not timed.
Row run(const std::string& name, Result<Stepper> made, const Trajectory* reference) {
    Row row;
    row.name = name;
    if (!made.isOk()) {
        row.failure = made.status().message();
        return row;
    }
    Stepper& s = made.value();
    Trajectory frames;
    double totalMs = 0.0, totalIterations = 0.0;
    for (int f = 0; f < kRunFrames; ++f) {
        const auto start = Clock::now();
        if (Status st = s.step(); !st) {
            row.failure = "frame " + std::to_string(f) + ": " + st.message();
            return row;
        }
        if (f > 0) totalMs += msSince(start);
        totalIterations += s.iterations();
        row.strain = std::max(row.strain, s.strain());
        if (f < kErrorFrames) frames.push_back(s.positions());
    }
    row.ms = totalMs / (kRunFrames - 1);
    row.iterations = totalIterations / kRunFrames;
    row.sag = kPatchHeight - lowestY(s.positions());
    if (reference) row.errorMm = rmsMm(frames, *reference);
    return row;
}

/// Backward Euler at dt/16 and dt/32, Newton to convergence (multigrid PCG to 1e-10 per Newton
/// iteration), extrapolated (first order: 2 x_32 - x_16);
/// cached on disk. outSelfErrorMm: the extrapolation's correction, an estimate of the error left in
/// the dt/32 run.
Result<Trajectory> reference(int vertices, const std::string& directory, std::FILE* out, double& outSelfErrorMm) {
    const std::string path = directory + "/reference_" + std::to_string(vertices) + ".bin";
    const std::size_t n = std::size_t(vertices) * vertices;
    Trajectory fine(kErrorFrames, std::vector<Vec3>(n)), ref = fine;
    std::ifstream in(path, std::ios::binary);
    uint32_t header[4] = {};
    if (in && in.read(reinterpret_cast<char*>(header), sizeof header) && header[0] == kCacheVersion &&
        header[1] == uint32_t(vertices) && header[2] == uint32_t(kErrorFrames)) {
        bool ok = true;
        for (auto* t : {&fine, &ref})
            for (auto& f : *t) ok = ok && bool(in.read(reinterpret_cast<char*>(f.data()), n * sizeof(Vec3)));
        if (ok) {
            outSelfErrorMm = rmsMm(fine, ref);
            return ref;
        }
    }
    std::fprintf(out, "  computing the %d^2 reference (backward Euler at dt/%d and dt/%d, Newton to 1e-8; cached in %s) ...\n",
                 vertices, kReferenceFine / 2, kReferenceFine, path.c_str());
    std::fflush(out);
    Trajectory half;
    for (int substeps : {kReferenceFine / 2, kReferenceFine}) {
        ImplicitRun implicit;
        implicit.substeps = substeps;
        implicit.converged = true;
        auto made = implicit.make(vertices, 1e-10);
        if (!made.isOk()) return made.status();
        Trajectory& target = substeps == kReferenceFine ? fine : half;
        target.clear();
        for (int f = 0; f < kErrorFrames; ++f) {
            if (Status s = made.value().step(); !s) return s;
            target.push_back(made.value().positions());
        }
    }
    for (int f = 0; f < kErrorFrames; ++f)
        for (std::size_t v = 0; v < n; ++v) ref[f][v] = 2.0 * fine[f][v] - half[f][v];
    std::error_code ignored;
    std::filesystem::create_directories(directory, ignored);
    std::ofstream cache(path, std::ios::binary);
    const uint32_t write[4] = {kCacheVersion, uint32_t(vertices), uint32_t(kErrorFrames), 0};
    cache.write(reinterpret_cast<const char*>(write), sizeof write);
    for (const Trajectory* t : {&fine, &ref})
        for (const auto& f : *t) cache.write(reinterpret_cast<const char*>(f.data()), n * sizeof(Vec3));
    outSelfErrorMm = rmsMm(fine, ref);
    return ref;
}

void printRow(std::FILE* out, int vertices, const Row& row, double baselineMs) {
    if (!row.failure.empty()) {
        std::fprintf(out, "  %4d  %-40s FAILED: %s\n", vertices, row.name.c_str(), row.failure.c_str());
        return;
    }
    char error[32] = "     n/a";
    if (std::isfinite(row.errorMm)) std::snprintf(error, sizeof error, "%8.1f", row.errorMm);
    std::fprintf(out, "  %4d  %-40s %9.3f %8.0f %8.2f %s %7.3f %8.1fx\n", vertices, row.name.c_str(), row.ms,
                 row.iterations, 100.0 * row.strain, error, row.sag, baselineMs / row.ms);
    std::fflush(out);
}

std::string substepName(const cloth::SubstepSettings& s) {
    const bool newton = s.method == cloth::SubstepMethod::Newton;
    std::string name = std::string(newton ? "substep-newton" : "substep-pd") + " s=" + std::to_string(s.substeps);
    if (newton || s.iterations > 1) name += (newton ? " cg=" : " it=") + std::to_string(s.iterations);
    if (newton && !s.warmStart) name += " cold";
    if (s.strainLimit > 0.0) {
        char limit[32];
        std::snprintf(limit, sizeof limit, " limit=%.1f%%", 100.0 * s.strainLimit);
        name += limit;
    }
    return name;
}

} // namespace

bool runSolverFront(std::FILE* out, const SolverFrontOptions& options) {
    std::fprintf(out,
                 "\nSolver front: the bench sheet (Provot springs, no Rayleigh damping), one thread, 1/60 s frames.\n"
                 "  ms        mean wall time per frame over frames 2-%d (the first builds factors)\n"
                 "  iters     per frame: CG iterations (PCG) or substeps x local/global iterations\n"
                 "  strain    max edge strain over %d frames (%.0f s) [%%]\n"
                 "  err       RMS vertex distance to the converged small-step reference over the first\n"
                 "            %d frames [mm]\n"
                 "  sag       1 m - lowest y after %.0f s [m]; speed: baseline ms / ms\n\n",
                 kRunFrames, kRunFrames, kRunFrames * kDt, kErrorFrames, kRunFrames * kDt);
    std::fprintf(out, "  %4s  %-40s %9s %8s %8s %8s %7s %9s\n", "N", "solver", "ms", "iters", "strain%", "err_mm",
                 "sag_m", "speed");
    bool ok = true;
    struct Bar {
        Row best, pcg;
        double bulletMs = NAN;
        bool have = false;
    } bar;
    for (int vertices : options.resolutions) {
        Trajectory ref;
        const bool withReference = std::find(options.referenceResolutions.begin(), options.referenceResolutions.end(),
                                             vertices) != options.referenceResolutions.end();
        if (withReference) {
            double selfError = 0.0;
            auto made = reference(vertices, options.cacheDirectory, out, selfError);
            if (!made.isOk()) {
                std::fprintf(out, "  %4d  reference FAILED: %s\n", vertices, made.status().message().c_str());
                ok = false;
                continue;
            }
            ref = std::move(made).value();
            std::fprintf(out, "  %4d  %-40s extrapolation moved it %.2f mm\n", vertices, "reference", selfError);
        }
        const Trajectory* refPtr = withReference ? &ref : nullptr;

        ImplicitRun baseline;
        const Row pcg = run("pcg (baseline, dt)", baseline.make(vertices, 1e-3), refPtr);
        printRow(out, vertices, pcg, pcg.ms);
        ok = ok && pcg.failure.empty();
        if (vertices <= 65) {
            ImplicitRun four;
            four.substeps = 4;
            const Row pcg4 = run("pcg 4 substeps", four.make(vertices, 1e-3), refPtr);
            printRow(out, vertices, pcg4, pcg.ms);
        }

        std::vector<cloth::SubstepSettings> configs;
        for (int substeps : {2, 3, 4, 6, 8}) {
            for (int iterations : {2, 3, 4, 5, 6}) {
                cloth::SubstepSettings s;
                s.method = cloth::SubstepMethod::Newton;
                s.substeps = substeps;
                s.iterations = iterations;
                s.strainLimit = 0.045;
                configs.push_back(s);
                // CG from zero in every substep, for what the warm start buys.
                if ((substeps == 3 || substeps == 4) && (iterations == 3 || iterations == 4)) {
                    s.warmStart = false;
                    configs.push_back(s);
                }
            }
        }
        for (int substeps : {8, 16, 32}) {
            cloth::SubstepSettings s;
            s.method = cloth::SubstepMethod::LocalGlobal;
            s.substeps = substeps;
            s.iterations = 1;
            s.strainLimit = 0.045;
            configs.push_back(s);
        }
        for (const cloth::SubstepSettings& s : configs) {
            SubstepRun substep;
            substep.settings = s;
            const Row row = run(substepName(s), substep.make(vertices), refPtr);
            printRow(out, vertices, row, pcg.ms);
            ok = ok && row.failure.empty();
            if (vertices == 65 && row.failure.empty() && pcg.failure.empty() && row.strain <= 0.05 &&
                !(row.errorMm > pcg.errorMm) && (!bar.have || row.ms < bar.best.ms)) {
                bar.best = row;
                bar.have = true;
            }
        }

        BulletPatch bullet(vertices);
        Row b;
        b.name = "bullet btSoftBody (default)";
        double bulletMs = 0.0;
        for (int f = 0; f < kRunFrames; ++f) {
            const auto start = Clock::now();
            bullet.step();
            if (f > 0) bulletMs += msSince(start);
            b.strain = std::max(b.strain, bullet.maxEdgeStrain());
        }
        b.ms = bulletMs / (kRunFrames - 1);
        b.sag = kPatchHeight - bullet.lowestY();
        b.iterations = 1;
        printRow(out, vertices, b, pcg.ms);
        if (vertices == 65) {
            bar.pcg = pcg;
            bar.bulletMs = b.ms;
        }
        std::fprintf(out, "\n");
    }
    if (bar.have) {
        std::fprintf(out,
                     "BAR solver65 solver=\"%s\" ms=%.3f strain=%.4f traj_err_mm=%.1f pcg_ms=%.3f pcg_strain=%.4f "
                     "pcg_traj_err_mm=%.1f bullet_ms=%.3f speedup=%.1f\n\n",
                     bar.best.name.c_str(), bar.best.ms, bar.best.strain, bar.best.errorMm, bar.pcg.ms, bar.pcg.strain,
                     bar.pcg.errorMm, bar.bulletMs, bar.pcg.ms / bar.best.ms);
    } else if (std::find(options.resolutions.begin(), options.resolutions.end(), 65) != options.resolutions.end()) {
        std::fprintf(out, "BAR solver65 solver=none (no configuration within the baseline's error and 5%% strain)\n\n");
    }
    std::fflush(out);
    return ok;
}

} // namespace cc::bench
