# Compile options shared by crowdcloth's own targets. Applied per target (no directory-wide flags),
# so a host project that embeds crowdcloth keeps its own settings.
function(cc_target_options target)
    target_compile_options(${target} PRIVATE
        -Wall -Wextra -Wpedantic -Wshadow -Wno-unknown-pragmas
        # Determinism: no fused multiply-add contraction, no fast-math (STYLE.md §6).
        -ffp-contract=off
        ${CC_ARCH_FLAGS})
    if(CC_WARNINGS_AS_ERRORS)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
    if(CC_ENABLE_ASSERTS)
        target_compile_definitions(${target} PRIVATE CC_ENABLE_ASSERTS=1)
    endif()
endfunction()

# A library of the module: unity build when CC_UNITY_LIBRARIES asks for it.
function(cc_library_options target)
    cc_target_options(${target})
    if(CC_UNITY_LIBRARIES)
        set_target_properties(${target} PROPERTIES UNITY_BUILD ON)
        # GCC reads a unity file's included .cpp as a header, so a class holding a type from that
        # .cpp's anonymous namespace draws -Wsubobject-linkage; one file per unit has no such issue.
        if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
            target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
        endif()
    endif()
endfunction()

# An internal static library of the module: its headers are seen only inside this build (never
# installed), and its archive is named crowdcloth_<part> so an install does not add a libcc_*.a
# to a host's lib folder.
function(cc_internal_library target part)
    add_library(${target} STATIC ${ARGN})
    add_library(crowdcloth::${part} ALIAS ${target})
    set_target_properties(${target} PROPERTIES OUTPUT_NAME crowdcloth_${part})
    target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
    cc_library_options(${target})
    set_property(GLOBAL APPEND PROPERTY CC_INTERNAL_LIBRARIES ${target})
endfunction()

# A public library of the module (static or shared, installed): its version, its export macro
# <base>_API in <build>/include/crowdcloth/<header> (what the shared build exports; empty when
# static, where <base>_STATIC is defined for it and its users), and its public include dirs.
function(cc_public_library target base header)
    set_target_properties(${target} PROPERTIES
        VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
    generate_export_header(${target} BASE_NAME ${base} EXPORT_MACRO_NAME ${base}_API
                           STATIC_DEFINE ${base}_STATIC
                           EXPORT_FILE_NAME ${PROJECT_BINARY_DIR}/include/crowdcloth/${header})
    if(NOT BUILD_SHARED_LIBS)
        target_compile_definitions(${target} PUBLIC ${base}_STATIC)
    endif()
    target_include_directories(${target} PUBLIC
        $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
        $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
        $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    cc_library_options(${target})
endfunction()
