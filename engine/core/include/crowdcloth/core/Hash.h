#pragma once

#include <cstddef>
#include <cstdint>

namespace cc {

/// FNV-1a's offset basis: the digest of nothing, where a running hash starts.
constexpr uint64_t kHashSeed = 1469598103934665603ull;

/// FNV-1a over raw bytes: a bitwise digest of simulation state for determinism tests and replays.
inline uint64_t hashBytes(const void* data, std::size_t size, uint64_t seed = kHashSeed) {
    const auto* p = static_cast<const unsigned char*>(data);
    uint64_t h = seed;
    for (std::size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

} // namespace cc
