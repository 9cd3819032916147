// Multigrid against block-Jacobi PCG: one implicit step of the bench's warmed-up sheet at every
// resolution, on one thread, and the coarsening variants of the multigrid preconditioner side by
// side. Ends with the machine-readable BAR line.
//
// Protocol: a multigrid simulation of the sheet runs kWarmupSteps steps; each solver then takes
// that state in a fresh simulation, takes one step untimed (its warm start and, for multigrid, its
// hierarchy come from there, as they would in a running simulation) and then kTimedSteps timed
// steps; the table shows their mean. Warming up with multigrid keeps the run under a minute (30
// block-Jacobi warm-up steps at 129^2 alone take about as long).

#include "Benchmarks.h"
#include "crowdcloth/cloth/ImplicitEulerIntegrator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace cc::bench {

using cloth::ClothSimulation;
using cloth::CoarseningKind;
using cloth::IntegratorKind;

namespace {

constexpr int kTimedSteps = 3;

struct Measurement {
    double iterations = 0.0;    // per step
    double milliseconds = 0.0;  // per step
    int levels = 0;
    double operatorComplexity = 0.0;
    bool ok = false;
};

// The 4-8 hierarchy's level-to-level interpolation of the sheet's grid (2^k squares per side),
// finest first, as lod/ would hand it in: a Union Jack level drops its valence-4 vertices (the
// midpoints of the axis edges along their odd coordinate), a diamond level the centres of the
// coarse squares (midpoints of the alternating diagonals).
// (tests/support/GridProlongations.h holds the same construction for the tests.)
std::vector<SparseInterpolation> gridProlongations(const RectanglePanel& panel) {
    const int n = int(panel.columns);
    const auto at = [&](int i, int j) { return j * (n + 1) + i; };
    std::vector<int> current;
    current.reserve(std::size_t(n + 1) * std::size_t(n + 1));
    for (int v = 0; v < (n + 1) * (n + 1); ++v) current.push_back(v);
    std::vector<SparseInterpolation> levels;
    for (int s = 1; s < n; s *= 2) {
        for (bool diamond : {true, false}) {
            std::vector<int> index((n + 1) * (n + 1), -1), next;
            for (int v : current) {
                const int i = v % (n + 1), j = v / (n + 1);
                if (diamond ? (i / s + j / s) % 2 == 0 : i % (2 * s) == 0 && j % (2 * s) == 0) {
                    index[v] = int(next.size());
                    next.push_back(v);
                }
            }
            SparseInterpolation p;
            p.sourceCount = uint32_t(next.size());
            const auto half = [&](int i, int j) {
                p.terms.push_back({uint32_t(index[at(i, j)]), 0.5});
            };
            for (int v : current) {
                const int i = v % (n + 1), j = v / (n + 1);
                if (index[v] >= 0) {
                    p.terms.push_back({uint32_t(index[v]), 1.0});
                } else if (diamond) {
                    (i / s) % 2 ? (half(i - s, j), half(i + s, j))
                                : (half(i, j - s), half(i, j + s));
                } else if (((i - s) / (2 * s) + (j - s) / (2 * s)) % 2 == 0) {
                    half(i - s, j - s), half(i + s, j + s);
                } else {
                    half(i + s, j - s), half(i - s, j + s);
                }
                p.rowStart.push_back(uint32_t(p.terms.size()));
            }
            levels.push_back(std::move(p));
            current = std::move(next);
        }
    }
    return levels;
}

enum class Variant { Jacobi, IndependentSet, SmoothedAggregation, Grid48, Grid48Pairs };

const char* variantName(Variant v) {
    switch (v) {
    case Variant::Jacobi: return "block-Jacobi PCG";
    case Variant::IndependentSet: return "multigrid, independent set (default)";
    case Variant::SmoothedAggregation: return "multigrid, smoothed aggregation";
    case Variant::Grid48: return "multigrid, 4-8 levels handed in, as given";
    case Variant::Grid48Pairs: return "multigrid, 4-8 levels handed in, paired";
    }
    return "?";
}

// One solver from the warmed-up state `warm` (see the protocol above).
Measurement measure(Variant variant, int vertices, const cloth::ClothState& warm) {
    const RectanglePanel panel = patchPanel(vertices);
    Result<ClothMesh> mesh = panel.build();
    Measurement m;
    if (!mesh.isOk()) return m;
    cloth::SimulationSettings settings;
    settings.integrator = variant == Variant::Jacobi ? IntegratorKind::ImplicitPcg
                                                     : IntegratorKind::ImplicitMultigrid;
    settings.gravity = Vec3(0.0, kGravity, 0.0);
    settings.parallel.maxThreads = 1;
    cloth::MultigridSettings& mg = settings.implicit.multigrid;
    if (variant == Variant::SmoothedAggregation)
        mg.coarsening = CoarseningKind::SmoothedAggregation;
    if (variant == Variant::Grid48 || variant == Variant::Grid48Pairs) {
        mg.prolongations = gridProlongations(panel);
        // As given: every 4-8 level is a multigrid level. Paired: the default minCoarsening
        // composes the levels, which only halve the mesh, two by two.
        if (variant == Variant::Grid48) mg.minCoarsening = 1.0;
    }
    auto created =
        ClothSimulation::create(mesh.value(), patchMaterial(settings.integrator), settings);
    if (!created.isOk()) return m;
    ClothSimulation& sim = *created.value();
    for (uint32_t corner :
         {panel.vertexIndex(0, panel.rows), panel.vertexIndex(panel.columns, panel.rows)}) {
        if (!sim.constraints().pin(corner, mesh.value().positions[corner])) return m;
    }
    sim.state() = warm;
    if (!sim.step(kDt)) return m;
    int iterations = 0;
    double seconds = 0.0;
    for (int i = 0; i < kTimedSteps; ++i) {
        const auto start = std::chrono::steady_clock::now();
        const Status s = sim.step(kDt);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!s) return m;
        iterations += sim.lastStats().iterations;
    }
    m.iterations = double(iterations) / kTimedSteps;
    m.milliseconds = 1e3 * seconds / kTimedSteps;
    const auto& implicit = static_cast<const cloth::ImplicitEulerIntegrator&>(sim.integrator());
    if (const cloth::MultigridHierarchy* h = implicit.multigrid().hierarchy()) {
        m.levels = h->levelCount();
        m.operatorComplexity = h->operatorComplexity();
    }
    m.ok = true;
    return m;
}

} // namespace

bool runMultigridReport(std::FILE* out) {
    std::fprintf(
        out,
        "\nMultigrid vs block-Jacobi PCG: one implicit step of the warmed-up sheet (%d steps of "
        "1/60 s), 1 thread, mean of %d steps\n",
        kWarmupSteps, kTimedSteps);
    std::fprintf(out, "  %-8s %-42s %9s %10s %7s %14s\n", "vertices", "solver", "it/step",
                 "ms/step", "levels", "op.complexity");
    const Variant variants[] = {Variant::Jacobi, Variant::IndependentSet,
                                Variant::SmoothedAggregation, Variant::Grid48,
                                Variant::Grid48Pairs};
    Measurement jacobi[4], multigrid[4];
    bool ok = true;
    for (int r = 0; r < 4; ++r) {
        const int n = kResolutions[r];
        auto warm = createPatchSimulation(
            {cloth::ForceModelKind::Continuum, IntegratorKind::ImplicitMultigrid, 1}, n);
        if (!warm.isOk() || !warmUp(*warm.value())) {
            std::fprintf(out, "  %d^2: warm-up failed\n", n);
            ok = false;
            continue;
        }
        for (Variant v : variants) {
            const Measurement m = measure(v, n, warm.value()->state());
            if (v == Variant::Jacobi) jacobi[r] = m;
            if (v == Variant::IndependentSet) multigrid[r] = m;
            const std::string size = std::to_string(n) + "^2";
            if (!m.ok) {
                std::fprintf(out, "  %-8s %-42s failed\n", size.c_str(), variantName(v));
                ok = false;
                continue;
            }
            std::fprintf(out, "  %-8s %-42s %9.1f %10.2f", size.c_str(), variantName(v),
                         m.iterations, m.milliseconds);
            if (m.levels > 0) std::fprintf(out, " %7d %14.2f", m.levels, m.operatorComplexity);
            std::fprintf(out, "\n");
        }
    }
    for (int r = 2; r < 4; ++r) {
        if (jacobi[r].ok && multigrid[r].ok) {
            std::fprintf(out, "  wall-clock ratio at %d^2: block Jacobi / multigrid = %.1f\n",
                         kResolutions[r], jacobi[r].milliseconds / multigrid[r].milliseconds);
        }
    }
    std::fprintf(
        out,
        "BAR iterations solver=multigrid-pcg it33=%.1f it65=%.1f it129=%.1f jacobi_it33=%.1f "
        "jacobi_it65=%.1f jacobi_it129=%.1f ms65=%.2f jacobi_ms65=%.2f\n",
        multigrid[1].iterations, multigrid[2].iterations, multigrid[3].iterations,
        jacobi[1].iterations, jacobi[2].iterations, jacobi[3].iterations, multigrid[2].milliseconds,
        jacobi[2].milliseconds);
    std::fflush(out);
    return ok;
}

} // namespace cc::bench
