#pragma once

namespace cc::test {

/// Heap allocations (global operator new) since the test executable started. Defined with the
/// replaced operator new in AllocationCounter.cpp, which an executable links in to count.
long allocationCount();

} // namespace cc::test
