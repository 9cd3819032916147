#!/usr/bin/env bash
# Static analysis of crowdcloth's own code (libraries, samples, tests; never third-party headers):
# cppcheck's warning, performance and portability checks (its style checks are opinions: implicit
# Span and Result conversions, raw loops), any finding fails the run. With CLANG_TIDY=1 also
# clang-tidy's checks of .clang-tidy over the libraries (about ten minutes on 2 cores, so not in CI).
# Called by run-tests.sh; needs the packages of install-deps.sh and a configured ./build.
set -euo pipefail
cd "$(dirname "$0")/.."
includes=()
for d in engine/src engine/include engine/core/include cloth/include collision/include lod/include \
         engine/character/include engine/import/include engine/import/src build/include tests samples; do
    includes+=(-I "$d")
done
start=$(date +%s)
cppcheck -q -j "$(nproc)" --std=c++17 --language=c++ --library=googletest --library=posix \
         --enable=warning,performance,portability --suppress=missingIncludeSystem --error-exitcode=1 \
         "${includes[@]}" cloth/src collision/src lod/src engine/src engine/core/src engine/character/src \
         engine/import/src samples tests
echo "analysis: cppcheck clean in $(($(date +%s) - start)) s"
if [ "${CLANG_TIDY:-0}" = 1 ]; then
    run-clang-tidy -quiet -p build -j "$(nproc)" "$PWD/(cloth|collision|lod|engine)/.*\.cpp$"
fi
