#!/usr/bin/env bash
# Configures ./build-asan: crowdcloth under AddressSanitizer + UndefinedBehaviorSanitizer with
# clang, its code carrying the edge coverage libFuzzer steers by, so that one build serves the fast
# test suites (scripts/run-sanitizers.sh, LeakSanitizer on at run time) and the fuzzers
# (scripts/run-fuzz.sh). Measured on the 2-core VM: 215-265 s to build both (three runs), where a
# gcc build of the suites took 452 s and a separate clang build of the fuzzers 274 s more; the
# suites run as fast as under gcc (183-220 s against 216). Coverage is the inline 8-bit counters
# and the PC table, all libFuzzer needs:
# -fsanitize=fuzzer-no-link's comparison tracing as well doubled the suites' run (397 s). The fuzz
# targets' own sources add -fsanitize=fuzzer (tests/fuzz/CMakeLists.txt).
# OpenMP off (clang's runtime would be libomp, not the Release build's libgomp): the kernels run
# serially here and in parallel in the Release suites; the World's own threads (TaskPool) still run.
# Warnings are errors: this is the one clang build of the engine and its tests, so it keeps
# crowdcloth clean for clang hosts too. Run by both scripts; needs install-deps.sh's packages.
set -euo pipefail
cd "$(dirname "$0")/.."

san="-fsanitize=address,undefined -fsanitize-coverage=inline-8bit-counters,pc-table -fno-omit-frame-pointer"
san+=" -fno-sanitize-recover=undefined"
# A build-asan of another compiler (gcc's, before this script) starts afresh: CMake cannot change a
# build's compiler.
if [ -f build-asan/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' build-asan/CMakeCache.txt; then
    rm -rf build-asan
fi
mkdir -p build-asan
# -O2 -g1 for the libraries: Eigen is slow without inlining; line tables for the reports' stacks.
# Tests at -O1 (CC_TEST_SOURCE_FLAGS): they build faster and their own code is not the hot path.
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DCMAKE_C_FLAGS="$san" -DCMAKE_CXX_FLAGS="$san" \
      -DCMAKE_EXE_LINKER_FLAGS="$san" -DCMAKE_SHARED_LINKER_FLAGS="$san" \
      -DCC_BUILD_SAMPLES=OFF -DCC_WITH_OPENMP=OFF -DCC_BUILD_FUZZERS=ON -DCC_WARNINGS_AS_ERRORS=ON \
      -DCC_UNITY_LIBRARIES=ON -DCC_UNITY_TESTS=ON -DCC_TEST_SOURCE_FLAGS=-O1 > build-asan/configure.log
