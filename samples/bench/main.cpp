// cc_bench: crowdcloth's solvers on the bench sheet against each other, against the converged
// small-step reference and against Bullet's btSoftBody; then the Google Benchmark cases (one step
// of each setup, the PCG solve alone, memory bandwidth) and a summary that combines them.
//
// Usage: cc_bench [--front-only | --skip-front] [--front-resolutions=17,33,65] [--with-129-reference]
//                 [--multigrid-only] [Google Benchmark flags]
//   e.g. cc_bench --skip-front --benchmark_filter='Step/.*/65' --benchmark_min_time=0.05
// Our tables and BAR lines go to stdout; for machine-readable Google Benchmark results use
// --benchmark_out=FILE --benchmark_out_format=json.
#include "Benchmarks.h"
#include "BulletPeer.h"
#include "MachineInfo.h"
#include "RunSummary.h"
#include "SolverFront.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>

namespace {

void printHelp() {
    std::printf(
        "cc_bench [--front-only | --skip-front] [--front-resolutions=LIST] [--with-129-reference]\n"
        "         [--multigrid-only] [benchmark flags]\n"
        "  --front-only            run the solver front only (ms, strain, error against the\n"
        "                          converged reference, sag; the BAR solver65 line)\n"
        "  --skip-front            run the Google Benchmark cases only\n"
        "  --front-resolutions=L   comma-separated vertices per side (default 17,33,65,129)\n"
        "  --with-129-reference    also measure the error at 129^2 (its reference takes ~10 min\n"
        "                          the first time; cached in ./cc_bench_cache)\n"
        "  --multigrid-only        multigrid vs block-Jacobi PCG per resolution, then exit (< 1 min)\n\n");
    benchmark::PrintDefaultHelp();
}

std::vector<int> parseList(const char* text) {
    std::vector<int> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(std::atoi(item.c_str()));
    return out;
}

} // namespace

int main(int argc, char** argv) {
    // Take our own flags out before Benchmark parses the rest (it rejects unknown ones).
    bool frontOnly = false, skipFront = false, multigridOnly = false;
    cc::bench::SolverFrontOptions front;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--front-only") == 0) {
            frontOnly = true;
        } else if (std::strcmp(argv[i], "--skip-front") == 0) {
            skipFront = true;
        } else if (std::strncmp(argv[i], "--front-resolutions=", 20) == 0) {
            front.resolutions = parseList(argv[i] + 20);
        } else if (std::strcmp(argv[i], "--with-129-reference") == 0) {
            front.referenceResolutions.push_back(129);
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
    if (frontOnly && skipFront) {
        std::fprintf(stderr, "cc_bench: --front-only and --skip-front exclude each other\n");
        return 1;
    }
    for (int n : front.resolutions) {
        if (n < 2 || n > 1025) {
            std::fprintf(stderr, "cc_bench: --front-resolutions: %d vertices per side is outside [2, 1025]\n", n);
            return 1;
        }
    }

    cc::bench::printMachineHeader(stdout);
    std::printf("  peer       %s, single-threaded\n", cc::bench::bulletDescription().c_str());
    if (multigridOnly) return cc::bench::runMultigridReport(stdout) ? 0 : 1;
    bool ok = true;
    if (!skipFront) ok = cc::bench::runSolverFront(stdout, front);
    if (frontOnly) return ok ? 0 : 1;
    ok = cc::bench::runMultigridReport(stdout) && ok;

    cc::bench::registerStepBenchmarks();
    cc::bench::registerPcgSolveBenchmarks();
    cc::bench::registerBandwidthBenchmarks();
    cc::bench::RecordingReporter reporter{
        std::unique_ptr<benchmark::BenchmarkReporter>(benchmark::CreateDefaultDisplayReporter())};
    benchmark::RunSpecifiedBenchmarks(&reporter);
    cc::bench::printRunSummary(stdout, reporter);
    benchmark::Shutdown();
    return ok ? 0 : 1;
}
