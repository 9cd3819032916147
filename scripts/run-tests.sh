#!/usr/bin/env bash
# Installs dependencies, builds, runs cppcheck and clang-tidy on the project's code
# (scripts/run-analysis.sh) and every test through CTest; then builds the consumer projects
# against an install (scripts/check-consumers.sh); then the fast tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer (scripts/run-sanitizers.sh); then
# libFuzzer on the import gate, the World and the C API (scripts/run-fuzz.sh, fuzzers from the
# sanitizer build) beside the World's concurrency tests under ThreadSanitizer (scripts/run-tsan.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bash scripts/run-analysis.sh
# One test process per core. Tests use OpenMP inside, and two 2-thread processes on 2 cores make
# spinning OpenMP barriers crawl: its workers sleep when idle instead (results do not depend on it).
# Measured on the 2-core VM: 157 s for the Release suites in parallel, about twice that serially.
OMP_WAIT_POLICY=passive ctest --test-dir build --output-on-failure --timeout 900 -j "$(nproc)"
bash scripts/check-consumers.sh
bash scripts/run-sanitizers.sh
# The fuzzer runs one process, the TSan build wants both cores: overlapped, they save a minute of
# CI's time. The fuzzer's output follows TSan's; either failing fails the run.
mkdir -p build-fuzz
bash scripts/run-fuzz.sh > build-fuzz/run.log 2>&1 &
fuzz=$!
tsan_status=0
bash scripts/run-tsan.sh || tsan_status=$?
fuzz_status=0
wait "$fuzz" || fuzz_status=$?
cat build-fuzz/run.log
[ "$tsan_status" -eq 0 ] && [ "$fuzz_status" -eq 0 ]
