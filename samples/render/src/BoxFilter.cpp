#include "BoxFilter.h"

#include <cstddef>

namespace cc::render {

void boxFilterAndFlip(const uint8_t* samples, int factor, int width, int height, uint8_t* image) {
    const std::size_t sampleRow = std::size_t(width) * factor * 4;
    const unsigned count = unsigned(factor * factor);
    for (int y = 0; y < height; ++y) {
        uint8_t* out = image + std::size_t(height - 1 - y) * width * 4;
        const uint8_t* block = samples + std::size_t(y) * factor * sampleRow;
        for (int x = 0; x < width; ++x) {
            unsigned sum[4] = {0, 0, 0, 0};
            for (int sy = 0; sy < factor; ++sy) {
                const uint8_t* s = block + sy * sampleRow + std::size_t(x) * factor * 4;
                for (int sx = 0; sx < factor; ++sx, s += 4)
                    for (int c = 0; c < 4; ++c) sum[c] += s[c];
            }
            // Rounded to nearest, so a uniform block keeps its exact value.
            for (int c = 0; c < 4; ++c) out[std::size_t(x) * 4 + c] = uint8_t((sum[c] + count / 2) / count);
        }
    }
}

} // namespace cc::render
