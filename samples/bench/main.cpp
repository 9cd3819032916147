// cc_bench: one cloth step of crowdcloth against Bullet's btSoftBody on the same patch, the PCG
// solver alone, and memory bandwidth. First a quality comparison (strain and sag after 3 s, step
// cost), then the Google Benchmark cases, then a summary that combines them.
//
// Usage: cc_bench [--quality-only | --skip-quality] [--quality-full] [--multigrid-only]
//                 [Google Benchmark flags]
//   e.g. cc_bench --skip-quality --benchmark_filter='Step/.*/65' --benchmark_min_time=0.05
// Our tables go to stdout; for machine-readable results use --benchmark_out=FILE
// --benchmark_out_format=json.
#include "Benchmarks.h"
#include "BulletPeer.h"
#include "MachineInfo.h"
#include "QualityReport.h"
#include "RunSummary.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <memory>

namespace {

void printHelp() {
    std::printf(
        "cc_bench [--quality-only | --skip-quality] [--quality-full] [benchmark flags]\n"
        "  --quality-only   run the 3 s quality comparison only\n"
        "  --skip-quality   run the benchmarks only\n"
        "  --quality-full   compare all six setups (and single-threaded PCG) at 33^2 and 65^2\n"
        "                   instead of the two PCG setups at 65^2 (adds about 4 minutes)\n"
        "  --multigrid-only multigrid vs block-Jacobi PCG per resolution, then exit (< 1 min)\n\n");
    benchmark::PrintDefaultHelp();
}

} // namespace

int main(int argc, char** argv) {
    // Take our own flags out before Benchmark parses the rest (it rejects unknown ones).
    bool qualityOnly = false, skipQuality = false, qualityFull = false, multigridOnly = false;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quality-only") == 0) {
            qualityOnly = true;
        } else if (std::strcmp(argv[i], "--skip-quality") == 0) {
            skipQuality = true;
        } else if (std::strcmp(argv[i], "--quality-full") == 0) {
            qualityFull = true;
        } else if (std::strcmp(argv[i], "--multigrid-only") == 0) {
            multigridOnly = true;
        } else {
            argv[kept++] = argv[i];
        }
    }
    argc = kept;
    argv[argc] = nullptr;
    benchmark::Initialize(&argc, argv, printHelp);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    if (qualityOnly && skipQuality) {
        std::fprintf(stderr, "cc_bench: --quality-only and --skip-quality exclude each other\n");
        return 1;
    }

    cc::bench::printMachineHeader(stdout);
    std::printf("  peer       %s, single-threaded\n", cc::bench::bulletDescription().c_str());
    if (multigridOnly) return cc::bench::runMultigridReport(stdout) ? 0 : 1;
    bool ok = true;
    if (!skipQuality) ok = cc::bench::runQualityReport(stdout, qualityFull);
    if (qualityOnly) return ok ? 0 : 1;
    ok = cc::bench::runMultigridReport(stdout) && ok;

    cc::bench::registerStepBenchmarks();
    cc::bench::registerPcgSolveBenchmarks();
    cc::bench::registerBandwidthBenchmarks();
    cc::bench::RecordingReporter reporter(
        std::unique_ptr<benchmark::BenchmarkReporter>(benchmark::CreateDefaultDisplayReporter()));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    cc::bench::printRunSummary(stdout, reporter);
    benchmark::Shutdown();
    return ok ? 0 : 1;
}
