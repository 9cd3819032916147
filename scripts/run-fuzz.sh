#!/usr/bin/env bash
# Fuzzes with libFuzzer under AddressSanitizer + UndefinedBehaviorSanitizer (Debian's clang), each
# target for FUZZ_SECONDS (default 20) from its committed seeds and findings (the World and the C
# API from this build's findings alone, see below):
#   import  the import gate (tests/fuzz/FuzzImport.cpp: importCharacter on any bytes under any
#           extension; tests/fuzz/import_corpus)
#   world   any sequence of the World's calls with any values (FuzzWorld.cpp; corpus)
#   capi    the C API misused as a C host might (FuzzCApi.cpp; capi_corpus)
# FUZZ_TARGETS chooses (default all three). The fuzzers come from ./build-asan, the sanitizer
# suites' build (scripts/configure-sanitizers.sh; built here if run-sanitizers.sh has not). The
# run's new inputs stay in build-fuzz/; a crash, a leak, an input slower than 20 s or an allocation
# over 1 GB fails the run and leaves the input there (fix it, then commit it to the target's
# corpus). Called by run-tests.sh; needs the packages of install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-20}
targets=${FUZZ_TARGETS:-import world capi}

start=$(date +%s)
mkdir -p build-fuzz
touch build-fuzz/started  # findings newer than this are this run's
if [ ! -f build-asan/build.ninja ]; then bash scripts/configure-sanitizers.sh; fi
cmake --build build-asan --parallel "$(nproc)" --target $(for t in $targets; do echo "cc_fuzz_$t"; done)
built=$(date +%s)

# ASan refuses single allocations over 768 MB (below libFuzzer's 1024 MB limit), so a parse child's
# huge allocation ends in ASan's report and the child's own death (IsolatedImport.cpp), not in a
# libFuzzer oom- file for an input the gate contained; in the fuzzer's own process it is a finding.
export ASAN_OPTIONS="detect_leaks=1:max_allocation_size_mb=768"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"  # third-party leaks only
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
findings=0
for t in $targets; do
    found=build-fuzz/found_$t
    mkdir -p "$found"
    # libFuzzer runs its whole corpus before it mutates. The World's and the C API's committed
    # inputs step cloth (the World's two seconds each here, the C API's 430 forty seconds in all:
    # the whole run), and CTest's sanitizer run replays them (Fuzz*.CorpusRunsClean); so they start
    # from what earlier runs in this build found (measured from nothing: 15,000 inputs in 30 s).
    case "$t" in
        import) corpus=tests/fuzz/import_corpus ;;
        *) corpus= ;;
    esac
    # One job per core; -timeout and -malloc_limit_mb make a hang or a huge allocation a finding.
    ./build-asan/tests/fuzz/cc_fuzz_$t -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
        -malloc_limit_mb=1024 -print_final_stats=1 -artifact_prefix="$found/" "$found" $corpus \
        2>&1 | tail -n 25
    # Every file libFuzzer saves as crash-, oom-, leak- or timeout- is a real finding now
    # (a contained parse crash no longer writes one): new ones fail the run even where libFuzzer went on.
    new=$(find "$found" -maxdepth 1 -newer build-fuzz/started \
          \( -name 'crash-*' -o -name 'oom-*' -o -name 'leak-*' -o -name 'timeout-*' \) | wc -l)
    echo "fuzz $t: $new new finding file(s) in $found"
    findings=$((findings + new))
done
echo "fuzz: built in $((built - start)) s, fuzzed ${targets} for ${seconds} s each"
[ "$findings" -eq 0 ]
