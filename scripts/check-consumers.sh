#!/usr/bin/env bash
# Builds and runs the consumer projects of tests/consumers the way a host engine would: installs
# ./build (static, as configured by build.sh) into a temporary prefix and builds a C++ and a C99
# project against it with find_package; then a project that add_subdirectory()s this tree as a
# shared library (tests and samples off), whose exported symbols must all be crowdcloth's API.
# Called by run-tests.sh after ctest; needs ./build built.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=$(nproc)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

start=$(date +%s)
cmake --install build --prefix "$tmp/prefix" > "$tmp/install.log"
for consumer in cpp_package c99_package; do
    cmake -S "tests/consumers/$consumer" -B "$tmp/$consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
          -DCMAKE_PREFIX_PATH="$tmp/prefix" > "$tmp/$consumer.log"
    cmake --build "$tmp/$consumer" --parallel "$jobs" >> "$tmp/$consumer.log"
    "$tmp/$consumer/cc_consumer_${consumer%_package}"
done
packages=$(date +%s)

cmake -S tests/consumers/subdirectory -B "$tmp/subdirectory" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCROWDCLOTH_SOURCE_DIR="$root" -DBUILD_SHARED_LIBS=ON > "$tmp/subdirectory.log"
cmake --build "$tmp/subdirectory" --parallel "$jobs" >> "$tmp/subdirectory.log"
"$tmp/subdirectory/cc_consumer_subdirectory"
# Hidden by default: the shared library exports the C API, cc::World and what CC_API marks.
library=$(find "$tmp/subdirectory/crowdcloth" -name 'libcrowdcloth.so.*.*' | head -n 1)
exported=$(nm -DC --defined-only "$library" | awk '$2 ~ /^[TWBDRV]$/ { $1 = ""; $2 = ""; print }')
# Instantiations of std templates are exported whatever the visibility (libstdc++ marks namespace
# std default), so only crowdcloth's own names are checked.
own=$(grep -vE '^ *([a-z ]+ )?(std|__gnu_cxx)::' <<< "$exported" || true)
unexpected=$(grep -vE '^ *(cc_[a-z_]+|cc::(World|WorldDesc|ClothAssetDesc)::.*|cc::getVersion\(\)|cc::detail::(toCStatus|reportToC|stampError)(\[abi:cxx11\])?\(.*|_init|_fini|_edata|_end|__bss_start)$' <<< "$own" || true)
if [[ -n $unexpected ]]; then
    echo "check-consumers: $library exports symbols that CC_API does not mark:" >&2
    head -n 20 <<< "$unexpected" >&2
    trap - EXIT
    echo "check-consumers: kept $tmp for a look" >&2
    exit 1
fi
done_=$(date +%s)
echo "check-consumers: install + find_package consumers $((packages - start)) s," \
     "add_subdirectory (shared) $((done_ - packages)) s; $(wc -l <<< "$own") crowdcloth symbols exported"
