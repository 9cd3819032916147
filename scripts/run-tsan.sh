#!/usr/bin/env bash
# Builds the World's test suites with ThreadSanitizer (gcc) into ./build-tsan and runs the tests
# whose point is concurrency: the step's tasks on the World's own threads, on 1-4 host threads
# (std::thread), the same state for any thread count and batching, and calls refused while a step
# is open. OpenMP is off here: libgomp is not built with TSan, and the World's frame runs on its
# own std::thread pool (TaskPool) or the host's threads either way. Any report fails the run;
# scripts/tsan.supp holds the third-party suppressions (Embree, TBB), each with its reason.
# Called by run-tests.sh; needs the packages of install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/scripts/tsan.supp"

start=$(date +%s)
# -O1 -g1: builds in about two minutes on 2 cores, line tables for the reports' stacks.
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCC_BUILD_SAMPLES=OFF -DCC_WITH_OPENMP=OFF -DCC_UNITY_LIBRARIES=ON -DCC_UNITY_TESTS=ON \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
      -DCMAKE_C_FLAGS="-fsanitize=thread" -DCMAKE_CXX_FLAGS="-fsanitize=thread" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread" > /dev/null
cmake --build build-tsan --parallel "$(nproc)" --target cc_engine_tests cc_engine_unit_tests
built=$(date +%s)

# The thread-count sweep (World.StateHashIsTheSameForAnyThreadCount) runs in the Release suites:
# under TSan it alone takes 80 s, and the host-thread tests below cover the same tasks.
./build-tsan/tests/engine/cc_engine_tests --gtest_brief=1 \
    --gtest_filter='HostJobs.*:World.StateHashDoesNotDependOnHowGarmentsAreBatched:World.HostTaskRunnerGivesTheSameStateAsOpenMp:WorldLifecycle.CallsWhileAStepIsOpen*:World.CapeFollowsAWalkingMannequin'
./build-tsan/tests/engine/cc_engine_unit_tests --gtest_brief=1 --gtest_filter='TaskPool.*'
echo "tsan: built in $((built - start)) s, ran in $(($(date +%s) - built)) s"
