#pragma once

#include <cstdint>
#include <type_traits>

namespace cc {

/// How much parallelism a kernel may use. 0 threads = OpenMP's default (OMP_NUM_THREADS).
/// Results never depend on this number: kernels partition work so that every sum is taken in a
/// fixed order (STYLE.md §6).
struct ParallelSettings {
    int maxThreads = 0;       ///< [-] upper bound on threads; 0 = OpenMP default, 1 = serial
    int64_t minParallel = 2048; ///< [-] loops shorter than this run serially (fork cost)
};

namespace detail {
void parallelForEachImpl(int64_t count, int maxThreads, void* context, void (*body)(void*, int64_t index));
void parallelForImpl(int64_t count, const ParallelSettings& settings, void* context,
                     void (*body)(void*, int64_t begin, int64_t end));
}

/// Runs body(begin, end) over [0, count) in fixed contiguous chunks, possibly in parallel.
/// The body must write only to data indexed by its own range.
template <typename Body>
void parallelFor(int64_t count, const ParallelSettings& settings, Body&& body) {
    detail::parallelForImpl(count, settings, &body, [](void* ctx, int64_t begin, int64_t end) {
        (*static_cast<std::remove_reference_t<Body>*>(ctx))(begin, end);
    });
}

/// Runs body(i) for every i in [0, count), handing out indices dynamically (for independent items
/// of uneven cost, such as garments). maxThreads 0 = OpenMP's default, 1 = serial. The body must
/// write only to data owned by item i, so the order of execution never changes the result.
template <typename Body>
void parallelForEach(int64_t count, int maxThreads, Body&& body) {
    detail::parallelForEachImpl(count, maxThreads, &body, [](void* ctx, int64_t index) {
        (*static_cast<std::remove_reference_t<Body>*>(ctx))(index);
    });
}

} // namespace cc
