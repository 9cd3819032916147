#pragma once

// Registration of the Google Benchmark cases, and the names the run summary looks them up by.

#include "BenchScenes.h"

#include <cstdio>
#include <string>

namespace cc::bench {

/// One garment step of each of our setups and of Bullet at every resolution (ClothStepBench.cpp).
void registerStepBenchmarks();
/// solveFilteredPcg alone on a 65^2 system matrix, per force model (PcgSolveBench.cpp).
void registerPcgSolveBenchmarks();
/// STREAM triad out of DRAM and out of L3, on 1 and on all threads (BandwidthBench.cpp).
void registerBandwidthBenchmarks();
/// Multigrid vs block-Jacobi PCG per resolution and the BAR line (MultigridBench.cpp).
bool runMultigridReport(std::FILE* out);

constexpr int kPcgSolveResolution = 65;  ///< vertices per side of the PcgSolve system
constexpr int kPcgSolveIterations = 50;  ///< fixed CG iterations per solve
constexpr int kTriadL3Megabytes = 2;     ///< [MB] per array: 3 arrays sit in L3, not in L2, and
                                         ///< match one 65^2 CG iteration's traffic (~6.6 MB)
constexpr int kTriadDramMegabytes = 64;  ///< [MB] per array: 3 arrays far exceed L3

/// Cases left out of the step benchmarks because one step takes more than ~2 s.
bool tooSlowToBenchmark(const OurSetup& setup, int vertices);

std::string stepBenchmarkName(const OurSetup& setup, int vertices);
std::string bulletStepBenchmarkName(int vertices);
std::string pcgSolveBenchmarkName(cloth::ForceModelKind model);
/// threads = 0: OpenMP's default, as the solver runs.
std::string triadBenchmarkName(int megabytesPerArray, int threads);

} // namespace cc::bench
