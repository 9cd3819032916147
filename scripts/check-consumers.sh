#!/usr/bin/env bash
# Builds and runs the consumer projects of tests/consumers the way a host engine would: installs
# ./build (static, as configured by build.sh) into a temporary prefix and builds a C++ and a C99
# project against it with find_package; then a project that add_subdirectory()s this tree as a
# shared library with its import library (tests and samples off), whose exported symbols must all
# be crowdcloth's API.
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

# No optimisation (an empty build type) and the libraries as unity builds: this build checks the
# integration and the exports, not speed or each file's includes (the Release build does). It
# compiles the whole module again, the most of this script: 75 s on 2 cores, 128 s one file a unit.
cmake -S tests/consumers/subdirectory -B "$tmp/subdirectory" -G Ninja -DCMAKE_BUILD_TYPE= \
      -DCROWDCLOTH_SOURCE_DIR="$root" -DBUILD_SHARED_LIBS=ON -DCC_UNITY_LIBRARIES=ON > "$tmp/subdirectory.log"
cmake --build "$tmp/subdirectory" --parallel "$jobs" >> "$tmp/subdirectory.log"
"$tmp/subdirectory/cc_consumer_subdirectory"
"$tmp/subdirectory/cc_consumer_subdirectory_c"
# Hidden by default: each shared library exports only the names its CC_API / CC_IMPORT_API marks.
# Instantiations of std templates are exported whatever the visibility (libstdc++ marks namespace
# std default), so only crowdcloth's own names are checked.
check_exports() { # library file name, extended regex of the names it may export
    local library exported unexpected
    library=$(find "$tmp/subdirectory/crowdcloth" -name "$1.so.*.*" | head -n 1)
    # Filtered by mangled name (std:: is St, __gnu_cxx:: 9__gnu_cxx; typeinfo and vtables ZT[ISV]),
    # then demangled. Assimp's inline wrappers (Assimp::Importer::ReadFile(std::string), ...) keep
    # the default visibility its ASSIMP_API classes give them: third-party, like std.
    exported=$(nm -D --defined-only "$library" | awk '$2 ~ /^[TWBDRV]$/ { print $3 }' |
               grep -vE '^_Z(T[ISV])?(N|NK)?(St|9__gnu_cxx|6Assimp)|^(_init|_fini|_edata|_end|__bss_start)$' |
               c++filt || true)
    unexpected=$(grep -vE "^($2)\$" <<< "$exported" || true)
    if [[ -n $unexpected ]]; then
        echo "check-consumers: $library exports symbols that its export macro does not mark:" >&2
        head -n 20 <<< "$unexpected" >&2
        trap - EXIT
        echo "check-consumers: kept $tmp for a look" >&2
        exit 1
    fi
    echo "check-consumers: $(basename "$library") exports $(wc -l <<< "$exported") names, all marked"
}
check_exports libcrowdcloth 'cc_[a-z_]+|cc::(World|WorldDesc|ClothAssetDesc|ErrorTable|ErrorCookDesc)::.*|cc::(errorTableKey|cookErrorTable|loadOrCookErrorTable)\(.*|cc::getVersion\(\)|cc::detail::(toCStatus|reportToC|stampError)(\[abi:cxx11\])?\(.*'
check_exports libcrowdcloth_import 'cc_[a-z_]+|cc::(importCharacter|exportCharacter)(\[abi:cxx11\])?\(.*|cc::ImportSettings::.*'
done_=$(date +%s)
echo "check-consumers: install + find_package consumers $((packages - start)) s," \
     "add_subdirectory (shared) $((done_ - packages)) s"
