#pragma once

namespace cc::test {

/// Heap allocations (global operator new) since the test executable started. Defined with the
/// replaced operator new in AllocationCounter.cpp, which an executable links in to count.
long allocationCount();
/// Of those, the ones Embree (or its TBB) made inside the library (its BVH builds), counted while
/// classifyEmbreeAllocations(true) (which slows every allocation down).
long embreeAllocationCount();
void classifyEmbreeAllocations(bool on);

} // namespace cc::test
