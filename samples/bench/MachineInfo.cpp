#include "MachineInfo.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace cc::bench {

namespace {

/// The value of the first "key : value" line of a /proc file whose key is `key`, or "unknown".
std::string procField(const char* path, const std::string& key) {
    std::ifstream file(path);
    for (std::string line; std::getline(file, line);) {
        if (line.compare(0, key.size(), key) != 0) continue;
        const std::size_t colon = line.find(':');
        if (colon == std::string::npos) continue;
        const std::size_t start = line.find_first_not_of(" \t", colon + 1);
        return start == std::string::npos ? std::string() : line.substr(start);
    }
    return "unknown";
}

std::string firstLine(const char* path) {
    std::ifstream file(path);
    std::string line;
    return std::getline(file, line) ? line : "unknown";
}

} // namespace

void printMachineHeader(std::FILE* out) {
    const char* ompThreads = std::getenv("OMP_NUM_THREADS");
    std::fprintf(out, "cc_bench: crowdcloth cloth step vs Bullet btSoftBody\n");
    std::fprintf(out, "  CPU        %s\n", procField("/proc/cpuinfo", "model name").c_str());
    std::fprintf(out, "  cores      %ld online (nproc)\n", sysconf(_SC_NPROCESSORS_ONLN));
    std::fprintf(out, "  L3         %s\n",
                 firstLine("/sys/devices/system/cpu/cpu0/cache/index3/size").c_str());
    std::fprintf(out, "  memory     %s\n", procField("/proc/meminfo", "MemTotal").c_str());
    // Two OpenMP threads on two cores stall at every barrier when anything else runs.
    std::fprintf(out, "  load avg   %s (timings assume an otherwise idle machine)\n",
                 firstLine("/proc/loadavg").c_str());
    std::fprintf(out, "  OpenMP     OMP_NUM_THREADS=%s\n",
                 ompThreads ? ompThreads : "(unset: one thread per core)");
    std::fprintf(out, "  compiler   %s, flags %s\n", __VERSION__, CC_BENCH_ARCH_FLAGS);
    std::fflush(out);
}

} // namespace cc::bench
