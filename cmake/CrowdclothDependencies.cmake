# Finds crowdcloth's dependencies from Debian 12 packages. Each failure names the package to
# install; scripts/install-deps.sh installs all of them.

macro(cc_require found what package)
    if(NOT ${found})
        message(FATAL_ERROR "crowdcloth needs ${what}: install the Debian package '${package}' "
                            "(or run: sudo bash scripts/install-deps.sh)")
    endif()
endmacro()

find_package(Eigen3 3.4 QUIET NO_MODULE)
cc_require(Eigen3_FOUND "Eigen 3.4" libeigen3-dev)

# SuiteSparse in Debian 12 ships neither CMake config nor pkg-config metadata (ECOSYSTEM.md §3.7).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
if(CHOLMOD_INCLUDE_DIR AND CHOLMOD_LIBRARY AND SUITESPARSECONFIG_LIBRARY)
    set(CC_CHOLMOD_FOUND TRUE)
endif()
cc_require(CC_CHOLMOD_FOUND "SuiteSparse CHOLMOD" libsuitesparse-dev)
if(NOT TARGET CHOLMOD::CHOLMOD)
    add_library(CHOLMOD::CHOLMOD INTERFACE IMPORTED)
    target_include_directories(CHOLMOD::CHOLMOD INTERFACE ${CHOLMOD_INCLUDE_DIR})
    target_link_libraries(CHOLMOD::CHOLMOD INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})
endif()

if(CC_WITH_OPENMP)
    find_package(OpenMP QUIET)
    cc_require(OpenMP_CXX_FOUND "OpenMP" "g++ (libgomp)")
endif()

# Embree 3's config is named 'embree' and calls find_package(TBB) (ECOSYSTEM.md §3.1).
find_package(embree 3 QUIET CONFIG)
cc_require(embree_FOUND "Embree 3" "libembree-dev libtbb-dev")

if(CC_BUILD_IMPORT)
    find_package(assimp QUIET CONFIG)
    cc_require(assimp_FOUND "assimp (or configure with -DCC_BUILD_IMPORT=OFF)" libassimp-dev)
endif()

if(CC_BUILD_SAMPLES OR CC_BUILD_TESTS)
    find_package(PkgConfig QUIET)
    cc_require(PKG_CONFIG_FOUND "pkg-config" pkg-config)
    pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
    cc_require(OSMESA_FOUND "OSMesa" libosmesa6-dev)
    pkg_check_modules(STB QUIET IMPORTED_TARGET stb)
    cc_require(STB_FOUND "stb (PNG writing)" libstb-dev)
endif()

if(CC_BUILD_TESTS)
    find_package(GTest QUIET)
    cc_require(GTest_FOUND "GoogleTest" "libgtest-dev libgmock-dev")
endif()

if(CC_BUILD_SAMPLES)
    find_package(benchmark QUIET CONFIG)
    cc_require(benchmark_FOUND "Google Benchmark" libbenchmark-dev)
    # Bullet's soft body is the peer the benchmarks compare against (not a crowdcloth dependency).
    find_package(Bullet QUIET)
    cc_require(BULLET_FOUND "Bullet Physics" libbullet-dev)
endif()
