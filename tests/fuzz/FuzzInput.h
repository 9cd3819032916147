// Reads a fuzzer's bytes as typed values for the fuzz targets that drive calls (FuzzWorld,
// FuzzCApi): plausible values mostly, the awkward ones (NaN, infinities, huge, negative) often.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace cc::fuzz {

/// Reads typed values off the fuzzer's bytes; zeros once they run out.
class Input {
public:
    Input(const uint8_t* data, std::size_t size) : mData(data), mSize(size) {}
    bool empty() const { return mAt >= mSize; }
    uint8_t byte() { return mAt < mSize ? mData[mAt++] : 0; }
    uint32_t u32() {
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v = v << 8 | byte();
        return v;
    }
    /// Mostly plausible values, sometimes the awkward ones.
    double real(double lo, double hi) {
        switch (byte() % 16) {
        case 0: return std::numeric_limits<double>::quiet_NaN();
        case 1: return std::numeric_limits<double>::infinity();
        case 2: return -std::numeric_limits<double>::infinity();
        case 3: return 0.0;
        case 4: return -1.0;
        case 5: return 1e300;
        case 6: return -hi;
        case 7: {
            double raw;
            const uint64_t bits = uint64_t(u32()) << 32 | u32();
            std::memcpy(&raw, &bits, sizeof raw);
            return raw;
        }
        default: return lo + (hi - lo) * (u32() / 4294967295.0);
        }
    }

private:
    const uint8_t* mData;
    std::size_t mSize;
    std::size_t mAt = 0;
};

} // namespace cc::fuzz
