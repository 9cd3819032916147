#!/usr/bin/env bash
# Builds crowdcloth's fast test suites with AddressSanitizer + UndefinedBehaviorSanitizer (clang,
# LeakSanitizer on; scripts/configure-sanitizers.sh) into ./build-asan, with the fuzz targets that
# scripts/run-fuzz.sh runs from the same build, and runs the suites (CTest label 'fast') under it.
# Any report fails the run. Called by run-tests.sh after the Release tests; needs the packages of
# install-deps.sh. Leaks inside third-party libraries are suppressed in scripts/lsan.supp (each
# with its reason).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

# Set for the build too: gtest_discover_tests runs every test executable once to list its tests.
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:strict_init_order=1"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

start=$(date +%s)
bash scripts/configure-sanitizers.sh
# Only what runs here: the fast suites. The *_slow_tests suites (label 'slow'), the samples'
# renderer and anything else no fast suite needs are left to the Release build.
fast_suites=$(ninja -C build-asan -t targets all | sed -nE 's/^(cc_[a-z_]+_tests): phony$/\1/p' |
              grep -v '_slow_tests$')
fast_suites="$fast_suites cc_fuzz_world_replay cc_fuzz_capi_replay cc_fuzz_import_replay"  # the fuzz corpora, under the sanitizers too
fast_suites="$fast_suites cc_fuzz_world cc_fuzz_capi cc_fuzz_import"  # the fuzzers, for run-fuzz.sh
cmake --build build-asan --parallel "$(nproc)" --target $fast_suites
built=$(date +%s)

# The times below were measured under gcc's ASan; clang's runs the whole of it about as fast
# (178-220 s over four runs against gcc's 216). Fast suites only: the *_slow_tests suites (label
# 'slow') are run by the Release tests. Also left to them: drapes against collision bodies that
# take 4-10 s in Release and 200 s and more each under ASan (measured: Drape.SheetComesToRest...
# 205 s), which alone would double this run; and the
# twisted tube's self-collision (84 s under ASan, the slowest left): SelfCollisionGarment's sheet
# drop runs the same code here. Also left out: the tests that repeat one run at 1, 2 and 4 threads
# to compare hashes (20-30 s each here; the single-threaded paths run in every other test and the
# threaded ones under TSan and in World.StateHashDoesNotDependOnHowGarmentsAreBatched), and the
# stiffest-cloth extreme (35 s; the soft-to-rigid sweep runs the same solver code).
slow_under_asan='^(Drape\.SheetComesToRestOnASphereMeshNoDeeperThanTheThickness|FastCollider\.(Capsule|MeshBody)SweptIntoASheetNeverPassesThroughWithContinuousCollision|SelfCollisionGarment\.TwistedTubeStaysFreeOfIntersections'
slow_under_asan+='|Determinism\.ThreadCountDoesNotChangeTheResult|World\.StateHashIsTheSameForAnyThreadCount|SelfCollisionGarment\.ResultDoesNotDependOnThreadCount'
slow_under_asan+='|Extremes\.ImplicitStaysBoundedAtTheStiffestClothWithHugeSteps'
# The two slowest left (43 and 19 s here): every garment kind and cut placed on four bodies (the
# placement code runs under ASan in every fitted-garment test) and the shadow check's crowd run
# twice to compare hashes (its windows run under ASan in the other ShadowCheck tests).
slow_under_asan+='|GarmentFit\.PlacedGarmentsStartWithinTheStrainLimit|ShadowCheck\.TheCrowdItMeasuresRunsBitForBitAsWithoutIt'
# And the error-table cache's two cooks (12 s here): a cook runs under ASan in
# CookIsDeterministicAndMeasuresEveryLevel; the cache around it is file handling.
slow_under_asan+='|ErrorTable\.LoadOrCookCachesByKeyAndReplacesWhatDoesNotRead)$'
status=0
# One test process per core, OpenMP workers sleeping when idle (see run-tests.sh).
OMP_WAIT_POLICY=passive ctest --test-dir build-asan --output-on-failure --timeout 900 -j "$(nproc)" -L fast \
    -E "$slow_under_asan" || status=$?
done_=$(date +%s)
echo "run-sanitizers: build $((built - start)) s (with the fuzzers), fast tests $((done_ - built)) s (ASan + UBSan + LSan)"
exit "$status"
