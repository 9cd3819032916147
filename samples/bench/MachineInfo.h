#pragma once

#include <cstdio>

namespace cc::bench {

/// Prints the facts that make timings comparable: CPU model, online cores, L3 size, memory, load
/// average, the OpenMP thread setting, the compiler and crowdcloth's instruction-set flags.
void printMachineHeader(std::FILE* out);

} // namespace cc::bench
