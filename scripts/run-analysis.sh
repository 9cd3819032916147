#!/usr/bin/env bash
# Static analysis of crowdcloth's own code (never third-party headers), any finding fails the run:
# - cppcheck's warning, performance and portability checks over libraries, samples and tests (its
#   style checks are opinions: implicit Span and Result conversions, raw loops);
# - clang-tidy's checks of .clang-tidy over the libraries, the code that ships in a host's engine;
#   CLANG_TIDY=all also over the tests and samples (about five minutes more on 2 cores).
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

# clang-tidy reads a clang build's compile commands, configured and not built (the generated
# headers come from configure): the libraries as unity builds, so that Eigen's and Embree's headers
# are parsed once per unit of about eight files rather than once per file (one minute, not ten).
# Off here: bugprone-suspicious-include, which flags the unity units' #include of each .cpp.
start=$(date +%s)
scope=libraries
header_filter='(cloth|collision|lod|engine)/(include|src)/'
samples=OFF
if [ "${CLANG_TIDY:-}" = all ]; then
    scope="libraries, tests and samples"
    header_filter='/(cloth|collision|lod|engine|tests|samples)/'
    samples=ON
fi
mkdir -p build-tidy
CC=clang CXX=clang++ cmake -S . -B build-tidy -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
      -DCC_UNITY_LIBRARIES=ON -DCC_UNITY_TESTS=ON -DCC_BUILD_SAMPLES=$samples > build-tidy/configure.log 2>&1 ||
    { cat build-tidy/configure.log; exit 1; }
python3 - "$PWD" "${CLANG_TIDY:-}" > build-tidy/units.txt <<'PY'
import json, re, sys
root, everything = sys.argv[1], sys.argv[2] == "all"
ours = re.compile(re.escape(root) + r"/(build-tidy/)?(cloth|collision|lod|engine)/")
for unit in sorted({e["file"] for e in json.load(open(root + "/build-tidy/compile_commands.json"))}):
    if unit.endswith(".cpp") or unit.endswith(".cxx"):
        if everything or ours.match(unit):
            print(unit)
PY
status=0
xargs -a build-tidy/units.txt -P "$(nproc)" -n 1 clang-tidy -quiet -p build-tidy --header-filter="$header_filter" \
      --checks=-bugprone-suspicious-include --warnings-as-errors='*' > build-tidy/findings.txt 2> build-tidy/stderr.txt ||
    status=$?
if [ "$status" -ne 0 ]; then
    grep -A3 -E "(warning|error):" build-tidy/findings.txt || cat build-tidy/stderr.txt
    echo "analysis: clang-tidy found the above in the $scope"
    exit 1
fi
echo "analysis: clang-tidy clean over the $scope ($(wc -l < build-tidy/units.txt) units) in $(($(date +%s) - start)) s"
