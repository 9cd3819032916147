#pragma once
// Supersampling's resolve step: averages factor x factor blocks of samples into pixels.

#include <cstdint>

namespace cc::render {

/// `samples` is RGBA at (factor * width) x (factor * height), bottom row first (OpenGL order);
/// `image` receives RGBA width x height, top row first (PNG order).
void boxFilterAndFlip(const uint8_t* samples, int factor, int width, int height, uint8_t* image);

} // namespace cc::render
