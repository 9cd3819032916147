// Memory bandwidth: the STREAM triad a[i] = b[i] + s * c[i], counted as STREAM does (24 bytes per
// element: two reads, one write; the write-allocate read is not counted).

#include "Benchmarks.h"
#include "crowdcloth/core/ParallelFor.h"

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

namespace cc::bench {

namespace {

void triad(benchmark::State& state, int megabytesPerArray, int threads) {
    const int64_t n = int64_t(megabytesPerArray) * (1 << 20) / int64_t(sizeof(double));
    // Split across threads as the PCG's loops are (parallelFor), whatever the array size.
    ParallelSettings parallel;
    parallel.maxThreads = threads;
    parallel.minParallel = 0;
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double scalar = 3.0;
    // Raw pointers, so the compiler sees no aliasing through the vectors and vectorises the loop.
    double* out = a.data();
    const double* x = b.data();
    const double* y = c.data();
    for (auto _ : state) { // NOLINT(clang-analyzer-deadcode.DeadStores) benchmark timing loop
        parallelFor(n, parallel, [&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) out[i] = x[i] + scalar * y[i];
        });
        benchmark::ClobberMemory();
    }
    benchmark::DoNotOptimize(a.data());
    state.counters["bytes/s"] =
        benchmark::Counter(24.0 * double(n) * double(state.iterations()),
                           benchmark::Counter::kIsRate, benchmark::Counter::OneK::kIs1000);
}

} // namespace

std::string triadBenchmarkName(int megabytesPerArray, int threads) {
    return "Triad/3x" + std::to_string(megabytesPerArray) + "MB/" +
           (threads == 0 ? std::string("allThreads") : std::to_string(threads) + "thread");
}

void registerBandwidthBenchmarks() {
    // NOLINTBEGIN(clang-analyzer-cplusplus.NewDeleteLeaks): benchmark's registry owns them
    for (int megabytes : {kTriadL3Megabytes, kTriadDramMegabytes}) {
        for (int threads : {1, 0}) {
            benchmark::RegisterBenchmark(
                triadBenchmarkName(megabytes, threads).c_str(),
                [megabytes, threads](benchmark::State& state) { triad(state, megabytes, threads); })
                ->Unit(benchmark::kMicrosecond)
                ->UseRealTime();
        }
    }
    // NOLINTEND(clang-analyzer-cplusplus.NewDeleteLeaks)
}

} // namespace cc::bench
