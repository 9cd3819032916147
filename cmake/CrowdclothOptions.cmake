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
