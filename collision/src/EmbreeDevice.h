#pragma once

#include <embree3/rtcore.h>
#include <xmmintrin.h>

#include <mutex>
#include <string>

#include "crowdcloth/collision/CollisionDevice.h"

namespace cc::collision {

struct CollisionDevice::Impl {
    RTCDevice device = nullptr;
    std::mutex errorMutex;  // Embree reports errors from whichever thread hit them
    std::string firstError;
};

namespace detail {

/// Sets flush-to-zero and denormals-are-zero for the Embree calls of a scope, as Embree
/// recommends, and restores the caller's MXCSR afterwards so the host's threads are not changed.
class ScopedFlushDenormals {
public:
    ScopedFlushDenormals() : mSaved(_mm_getcsr()) { _mm_setcsr(mSaved | 0x8040u); }
    ~ScopedFlushDenormals() { _mm_setcsr(mSaved); }
    ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
    ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

private:
    unsigned mSaved;
};

} // namespace detail
} // namespace cc::collision
