#pragma once
// A linear RGB colour, each channel in [0, 1].

#include <array>

namespace cc::render {

using Rgb = std::array<float, 3>;

} // namespace cc::render
