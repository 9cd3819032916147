// PCG alone: solveFilteredPcg on the system matrix a moving 65^2 patch assembled, with a fixed
// iteration count, so ns per vertex per CG iteration is measured without assembly and set-up.

#include "Benchmarks.h"
#include "crowdcloth/cloth/FilteredPcg.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace cc::bench {

using cloth::ImplicitEulerIntegrator;

namespace {

/// A warmed-up implicit simulation whose last assembled matrix is the system to solve, plus the
/// solver's inputs. Built on the case's first call and kept across Benchmark's repeated calls.
struct PcgSystem {
    std::unique_ptr<cloth::ClothSimulation> sim;
    std::vector<cloth::VertexFilter> filters;  // all free: every direction is solved
    std::vector<Vec3> b, z, dv;
    cloth::PcgWorkspace work;

    Status build(cloth::ForceModelKind model) {
        auto created = createPatchSimulation({model, cloth::IntegratorKind::ImplicitPcg, 0},
                                             kPcgSolveResolution);
        if (!created.isOk()) return created.status();
        sim = std::move(created.value());
        if (Status s = warmUp(*sim); !s) return s;
        const uint32_t n = sim->state().vertexCount();
        filters.assign(n, cloth::VertexFilter{});
        z.assign(n, Vec3::Zero());
        dv.assign(n, Vec3::Zero());
        // Varied so that CG does not converge early on a smooth right-hand side.
        b.resize(n);
        for (uint32_t i = 0; i < n; ++i) {
            b[i] = Vec3(std::sin(double(i)), std::cos(1.3 * double(i)), 1.0);
        }
        return Status::ok();
    }

    const cloth::BlockSparseMatrix& matrix() const {
        return static_cast<const ImplicitEulerIntegrator&>(sim->integrator()).systemMatrix();
    }
};

void pcgSolve(benchmark::State& state, PcgSystem& system, cloth::ForceModelKind model) {
    if (!system.sim) {
        if (Status s = system.build(model); !s) {
            system.sim.reset();
            state.SkipWithError(s.message().c_str());
            return;
        }
    }
    const cloth::BlockSparseMatrix& a = system.matrix();
    cloth::PcgSettings settings;
    settings.relativeTolerance = 1e-30;  // never reached: every solve runs kPcgSolveIterations
    settings.maxIterations = kPcgSolveIterations;
    const ParallelSettings parallel = system.sim->settings().parallel;

    int64_t iterations = 0;
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        std::fill(system.dv.begin(), system.dv.end(), Vec3::Zero());  // cold start each solve
        const cloth::PcgResult result = cloth::solveFilteredPcg(
            a, system.filters, system.b, system.z, system.dv, settings, parallel, system.work);
        iterations += result.iterations;
        benchmark::DoNotOptimize(system.dv.data());
    }
    const double n = a.size();
    const double blocksPerRow = double(a.blockCount()) / n;
    const double bytes = cloth::pcgBytesPerVertexIteration(blocksPerRow);
    using benchmark::Counter;
    state.counters["cgIters/solve"] = Counter(double(iterations), Counter::kAvgIterations);
    state.counters["timePerVertexIter"] =
        Counter(n * double(iterations), Counter::kIsRate | Counter::kInvert);
    state.counters["blocksPerRow"] = blocksPerRow;
    // The traffic pcgBytesPerVertexIteration accounts for, per second: compare with the triad.
    state.counters["modelBytes/s"] =
        Counter(bytes * n * double(iterations), Counter::kIsRate, Counter::OneK::kIs1000);
}

} // namespace

std::string pcgSolveBenchmarkName(cloth::ForceModelKind model) {
    return std::string("PcgSolve/") + forceModelName(model) + "/" +
           std::to_string(kPcgSolveResolution);
}

void registerPcgSolveBenchmarks() {
    // NOLINTBEGIN(clang-analyzer-cplusplus.NewDeleteLeaks): benchmark's registry owns them
    for (cloth::ForceModelKind model :
         {cloth::ForceModelKind::MassSpring, cloth::ForceModelKind::Continuum}) {
        auto system = std::make_shared<PcgSystem>();
        benchmark::RegisterBenchmark(
            pcgSolveBenchmarkName(model).c_str(),
            [system, model](benchmark::State& state) { pcgSolve(state, *system, model); })
            ->Unit(benchmark::kMicrosecond)
            ->UseRealTime();
    }
    // NOLINTEND(clang-analyzer-cplusplus.NewDeleteLeaks)
}

} // namespace cc::bench
