// Step benchmarks: the cost of one 1/60 s step of a moving patch, ours and Bullet's.

#include "Benchmarks.h"
#include "BulletPeer.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace cc::bench {

using cloth::ClothSimulation;
using cloth::IntegratorKind;

namespace {

/// The warmed-up scene of the case being measured. Benchmark calls a case's function several times
/// while it sizes the iteration count; keeping the scene pays the 30-step warm-up once per case
/// (the timed steps then continue the same evolving simulation).
class WarmScene {
public:
    Result<ClothSimulation*> ours(const OurSetup& setup, int vertices) {
        const std::string key = stepBenchmarkName(setup, vertices);
        if (key != mKey || !mOurs) {
            reset();
            auto sim = createPatchSimulation(setup, vertices);
            if (!sim.isOk()) return sim.status();
            if (Status s = warmUp(*sim.value()); !s) return s;
            mOurs = std::move(sim.value());
            mKey = key;
        }
        return mOurs.get();
    }

    BulletPatch& bullet(int vertices) {
        const std::string key = bulletStepBenchmarkName(vertices);
        if (key != mKey || !mBullet) {
            reset();
            mBullet = std::make_unique<BulletPatch>(vertices);
            for (int i = 0; i < kWarmupSteps; ++i) mBullet->step();
            mKey = key;
        }
        return *mBullet;
    }

    void reset() {
        mKey.clear();
        mOurs.reset();
        mBullet.reset();
    }

private:
    std::string mKey;
    std::unique_ptr<ClothSimulation> mOurs;
    std::unique_ptr<BulletPatch> mBullet;
};

void ourStep(benchmark::State& state, WarmScene& scene, OurSetup setup, int vertices) {
    auto acquired = scene.ours(setup, vertices);
    if (!acquired.isOk()) {
        state.SkipWithError(acquired.status().message().c_str());
        return;
    }
    ClothSimulation& sim = *acquired.value();
    int64_t cgIterations = 0, substeps = 0;
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        if (Status s = sim.step(kDt); !s) {
            state.SkipWithError(s.message().c_str());
            scene.reset();
            return;
        }
        cgIterations += sim.lastStats().iterations;
        substeps += sim.lastStats().substeps;
    }
    const double n = sim.state().vertexCount();
    using benchmark::Counter;
    state.counters["vertexSteps/s"] = Counter(n * double(state.iterations()), Counter::kIsRate);
    if (setup.integrator == IntegratorKind::ImplicitPcg) {
        state.counters["cgIters/step"] = Counter(double(cgIterations), Counter::kAvgIterations);
        // Seconds per vertex-iteration (an inverted rate). The whole step is charged to the CG
        // iterations, so this bounds the PcgSolve figure from above.
        state.counters["timePerVertexIter"] =
            Counter(n * double(cgIterations), Counter::kIsRate | Counter::kInvert);
    }
    // Explicit: stability substeps; implicit: > 1 when step-size control split a step.
    state.counters["substeps/step"] = Counter(double(substeps), Counter::kAvgIterations);
}

void bulletStep(benchmark::State& state, WarmScene& scene, int vertices) {
    BulletPatch& patch = scene.bullet(vertices);
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        if (patch.step() != 1) {
            state.SkipWithError("Bullet took other than one internal step");
            scene.reset();
            return;
        }
    }
    state.counters["vertexSteps/s"] = benchmark::Counter(
        double(patch.vertexCount()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

} // namespace

bool tooSlowToBenchmark(const OurSetup& setup, int vertices) {
    // Measured on the quiet 2-core reference machine at 129^2: a CHOLMOD step takes 2.2 s (a fresh
    // numeric factorisation every step), beyond the ~2 s budget per step; an explicit step takes
    // 0.7 s (~590 substeps) and an ImplicitPcg step 0.4-0.9 s, so those stay.
    return setup.integrator == IntegratorKind::ImplicitCholmod && vertices >= 129;
}

std::string stepBenchmarkName(const OurSetup& setup, int vertices) {
    return "Step/" + setupName(setup) + "/" + std::to_string(vertices);
}

std::string bulletStepBenchmarkName(int vertices) {
    return "Step/Bullet/" + std::to_string(vertices);
}

void registerStepBenchmarks() {
    // Shared by all step cases; they run one after another, so one warm scene at a time suffices.
    auto scene = std::make_shared<WarmScene>();
    for (int vertices : kResolutions) {
        for (const OurSetup& setup : allOurSetups()) {
            if (tooSlowToBenchmark(setup, vertices)) continue;
            benchmark::RegisterBenchmark(stepBenchmarkName(setup, vertices).c_str(),
                                         [scene, setup, vertices](benchmark::State& state) {
                                             ourStep(state, *scene, setup, vertices);
                                         })
                ->Unit(benchmark::kMillisecond)
                // OpenMP threads share the work: the benchmark thread's CPU time would mislead.
                ->UseRealTime();
        }
        benchmark::RegisterBenchmark(
            bulletStepBenchmarkName(vertices).c_str(),
            [scene, vertices](benchmark::State& state) { bulletStep(state, *scene, vertices); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
}

} // namespace cc::bench
