// Counts every global operator new of this test executable, so a test can check that a hot path
// allocates nothing (support/AllocationCounter.h). Kept in its own file so that no other code is
// compiled with the replaced operators in view. Out of memory aborts: the code under test does
// not use exceptions.
#include "support/AllocationCounter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> gAllocations{0};
}

long cc::test::allocationCount() { return gAllocations.load(); }

void* operator new(std::size_t size) {
    ++gAllocations;
    void* p = std::malloc(size ? size : 1);
    if (!p) std::abort();
    return p;
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
