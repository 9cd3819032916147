#include "RunSummary.h"

#include "Benchmarks.h"
#include "crowdcloth/cloth/FilteredPcg.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace cc::bench {

RecordingReporter::RecordingReporter(std::unique_ptr<benchmark::BenchmarkReporter> display)
    : mDisplay(std::move(display)) {}

bool RecordingReporter::ReportContext(const Context& context) {
    return mDisplay->ReportContext(context);
}

void RecordingReporter::ReportRuns(const std::vector<Run>& runs) {
    for (const Run& run : runs) {
        if (!run.error_occurred && run.run_type == Run::RT_Iteration) {
            mRuns[run.run_name.function_name] = run;
        }
    }
    mDisplay->ReportRuns(runs);
}

void RecordingReporter::Finalize() { mDisplay->Finalize(); }

const RecordingReporter::Run* RecordingReporter::find(const std::string& name) const {
    const auto it = mRuns.find(name);
    return it == mRuns.end() ? nullptr : &it->second;
}

namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

double counter(const RecordingReporter& runs, const std::string& name, const char* counterName) {
    const RecordingReporter::Run* run = runs.find(name);
    if (!run) return kMissing;
    const auto it = run->counters.find(counterName);
    return it == run->counters.end() ? kMissing : it->second.value;
}

/// [bytes/s] triad bandwidth on all threads, the thread count the solver uses.
double triadBandwidth(const RecordingReporter& runs, int megabytesPerArray) {
    return counter(runs, triadBenchmarkName(megabytesPerArray, 0), "bytes/s");
}

bool anyRan(const RecordingReporter& runs, const std::vector<std::string>& names) {
    for (const std::string& name : names) {
        if (runs.find(name)) return true;
    }
    return false;
}

void printBandwidth(std::FILE* out, const RecordingReporter& runs) {
    std::vector<std::string> triadNames;
    for (int megabytes : {kTriadL3Megabytes, kTriadDramMegabytes}) {
        for (int threads : {1, 0}) triadNames.push_back(triadBenchmarkName(megabytes, threads));
    }
    if (!anyRan(runs, triadNames)) return;
    std::fprintf(out, "\nMemory bandwidth, STREAM triad (24 B per element counted):\n");
    for (int megabytes : {kTriadL3Megabytes, kTriadDramMegabytes}) {
        const double one = counter(runs, triadBenchmarkName(megabytes, 1), "bytes/s");
        const double all = triadBandwidth(runs, megabytes);
        std::fprintf(out, "  3 x %2d MB (%s): %6.1f GB/s on 1 thread, %6.1f GB/s on all threads\n",
                     megabytes, megabytes == kTriadL3Megabytes ? "L3-resident" : "DRAM       ",
                     1e-9 * one, 1e-9 * all);
    }
}

void printRoofline(std::FILE* out, const RecordingReporter& runs) {
    if (!anyRan(runs, {pcgSolveBenchmarkName(cloth::ForceModelKind::MassSpring),
                       pcgSolveBenchmarkName(cloth::ForceModelKind::Continuum)})) {
        return;
    }
    const double l3 = triadBandwidth(runs, kTriadL3Megabytes);
    const double dram = triadBandwidth(runs, kTriadDramMegabytes);
    const double vertices = double(kPcgSolveResolution) * kPcgSolveResolution;
    std::fprintf(out,
                 "\nPCG roofline at %d^2 (%d CG iterations per solve, all threads).\n"
                 "  bound = bytes per vertex-iteration (pcgBytesPerVertexIteration) / triad\n"
                 "          bandwidth\n"
                 "  ratio = measured / bound (1 = bandwidth-bound)\n"
                 "  MB/iter = bytes one iteration streams over all vertices (against L2 and L3)\n",
                 kPcgSolveResolution, kPcgSolveIterations);
    std::fprintf(out, "  %-11s %10s %9s %9s %12s %11s %6s %13s %6s\n", "model", "blocks/row",
                 "MB/iter", "B/vtx-it", "measured ns", "L3 bound ns", "ratio", "DRAM bound ns",
                 "ratio");
    for (cloth::ForceModelKind model :
         {cloth::ForceModelKind::MassSpring, cloth::ForceModelKind::Continuum}) {
        const std::string name = pcgSolveBenchmarkName(model);
        const double blocksPerRow = counter(runs, name, "blocksPerRow");
        if (std::isnan(blocksPerRow)) continue;
        const double bytes = cloth::pcgBytesPerVertexIteration(blocksPerRow);
        const double measuredNs = 1e9 * counter(runs, name, "timePerVertexIter");
        const double l3Ns = 1e9 * bytes / l3, dramNs = 1e9 * bytes / dram;
        std::fprintf(out, "  %-11s %10.2f %9.2f %9.0f %12.3f %11.3f %6.2f %13.3f %6.2f\n",
                     forceModelName(model), blocksPerRow, bytes * vertices / (1 << 20), bytes,
                     measuredNs, l3Ns, measuredNs / l3Ns, dramNs, measuredNs / dramNs);
        const OurSetup step{model, cloth::IntegratorKind::ImplicitPcg, 0};
        const double stepNs =
            1e9 * counter(runs, stepBenchmarkName(step, kPcgSolveResolution), "timePerVertexIter");
        if (!std::isnan(stepNs)) {
            std::fprintf(out, "  %-11s   whole step charged to its CG iterations: %.3f ns\n", "",
                         stepNs);
        }
    }
}

void printSpeedVersusBullet(std::FILE* out, const RecordingReporter& runs) {
    std::vector<std::string> bulletNames;
    for (int vertices : kResolutions) bulletNames.push_back(bulletStepBenchmarkName(vertices));
    if (!anyRan(runs, bulletNames)) return;
    std::fprintf(out,
                 "\nVertex-steps per second relative to Bullet (step benchmarks). Bullet runs on\n"
                 "one thread; we use all threads from 65^2 up (vertex loops below\n"
                 "ParallelSettings::minParallel run serially):\n");
    std::fprintf(out, "  %-38s", "setup");
    for (int vertices : kResolutions) std::fprintf(out, " %8d^2", vertices);
    std::fprintf(out, "\n  %-38s", "Bullet [Mvertex-steps/s]");
    for (int vertices : kResolutions) {
        std::fprintf(out, " %10.3f",
                     1e-6 * counter(runs, bulletStepBenchmarkName(vertices), "vertexSteps/s"));
    }
    std::fprintf(out, "\n");
    for (const OurSetup& setup : allOurSetups()) {
        std::fprintf(out, "  %-38s", (setupName(setup) + " [x Bullet]").c_str());
        for (int vertices : kResolutions) {
            if (tooSlowToBenchmark(setup, vertices)) {
                std::fprintf(out, " %10s", "skipped");
                continue;
            }
            const double ours = counter(runs, stepBenchmarkName(setup, vertices), "vertexSteps/s");
            const double bullet = counter(runs, bulletStepBenchmarkName(vertices), "vertexSteps/s");
            std::fprintf(out, " %10.3f", ours / bullet);
        }
        std::fprintf(out, "\n");
    }
}

} // namespace

void printRunSummary(std::FILE* out, const RecordingReporter& runs) {
    if (runs.empty()) return;
    std::fprintf(out, "\nSummary (nan = filtered out or failed; skipped = a step takes > ~2 s)\n");
    printBandwidth(out, runs);
    printRoofline(out, runs);
    printSpeedVersusBullet(out, runs);
    std::fflush(out);
}

} // namespace cc::bench
