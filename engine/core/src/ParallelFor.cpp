#include "crowdcloth/core/ParallelFor.h"

#ifdef CC_HAVE_OPENMP
#include <omp.h>
#endif

namespace cc::detail {

void parallelForEachImpl(int64_t count, int maxThreads, void* context, void (*body)(void*, int64_t)) {
    if (count <= 0) return;
#ifdef CC_HAVE_OPENMP
    const int threads = maxThreads > 0 ? maxThreads : omp_get_max_threads();
    if (threads > 1 && count > 1 && !omp_in_parallel()) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int64_t i = 0; i < count; ++i) body(context, i);
        return;
    }
#else
    (void)maxThreads;
#endif
    for (int64_t i = 0; i < count; ++i) body(context, i);
}

void parallelForImpl(int64_t count, const ParallelSettings& settings, void* context,
                     void (*body)(void*, int64_t, int64_t)) {
    if (count <= 0) return;
#ifdef CC_HAVE_OPENMP
    const int threads = settings.maxThreads > 0 ? settings.maxThreads : omp_get_max_threads();
    if (threads > 1 && count >= settings.minParallel && !omp_in_parallel()) {
        // Static contiguous partition: each thread owns [begin, end); callers make results
        // independent of the partition, so the thread count never changes the answer.
#pragma omp parallel num_threads(threads)
        {
            const int64_t n = omp_get_num_threads(), t = omp_get_thread_num();
            const int64_t begin = count * t / n, end = count * (t + 1) / n;
            if (begin < end) body(context, begin, end);
        }
        return;
    }
#else
    (void)settings;
#endif
    body(context, 0, count);
}

} // namespace cc::detail
