// Counts every global operator new of this test executable, so a test can check that a hot path
// allocates nothing (support/AllocationCounter.h). Kept in its own file so that no other code is
// compiled with the replaced operators in view. Out of memory aborts: the code under test does
// not use exceptions.
//
// Every form is replaced, the nothrow and aligned ones too: the standard library allocates with
// them (std::stable_sort's buffer is `new (std::nothrow)`), and a form left to the runtime would
// both go uncounted and pair the runtime's operator new with our free (AddressSanitizer:
// alloc-dealloc-mismatch).
#include "support/AllocationCounter.h"

#include <dlfcn.h>
#include <execinfo.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>

namespace {
std::atomic<long> gAllocations{0};
std::atomic<long> gEmbreeAllocations{0};

std::atomic<bool> gClassify{false};

// Whether Embree (or its TBB) asked for the memory, a few frames up (through libstdc++ when it
// builds strings): its BVH builds allocate inside the library, which crowdcloth cannot prevent.
// Unwinding costs microseconds, so only while a test asks for it.
void countCaller(const void* caller) {
    if (!gClassify.load(std::memory_order_relaxed)) return;
    void* frames[12];
    const int n = backtrace(frames, 12);
    for (int i = 0; i < n; ++i) {
        Dl_info info;
        const void* at = i == 0 ? caller : frames[i];
        if (dladdr(at, &info) && info.dli_fname &&
            (std::strstr(info.dli_fname, "libembree") || std::strstr(info.dli_fname, "libtbb"))) {
            ++gEmbreeAllocations;
            return;
        }
    }
}

// The nothrow forms give nullptr when out of memory, the others abort.
void* allocate(std::size_t size, bool nothrow, const void* caller) {
    ++gAllocations;
    countCaller(caller);
    void* p = std::malloc(size ? size : 1);
    if (!p && !nothrow) std::abort();
    return p;
}

void* allocateAligned(std::size_t size, std::align_val_t alignment, bool nothrow, const void* caller) {
    ++gAllocations;
    countCaller(caller);
    const std::size_t a = std::max(std::size_t(alignment), sizeof(void*));
    // aligned_alloc wants a multiple of the alignment.
    void* p = std::aligned_alloc(a, (std::max<std::size_t>(size, 1) + a - 1) / a * a);
    if (!p && !nothrow) std::abort();
    return p;
}
} // namespace

long cc::test::allocationCount() { return gAllocations.load(); }
long cc::test::embreeAllocationCount() { return gEmbreeAllocations.load(); }
void cc::test::classifyEmbreeAllocations(bool on) { gClassify = on; }

void* operator new(std::size_t size) { return allocate(size, false, __builtin_return_address(0)); }
void* operator new[](std::size_t size) { return allocate(size, false, __builtin_return_address(0)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocate(size, true, __builtin_return_address(0)); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocate(size, true, __builtin_return_address(0)); }
void* operator new(std::size_t size, std::align_val_t a) { return allocateAligned(size, a, false, __builtin_return_address(0)); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocateAligned(size, a, false, __builtin_return_address(0)); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept { return allocateAligned(size, a, true, __builtin_return_address(0)); }
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept { return allocateAligned(size, a, true, __builtin_return_address(0)); }

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
