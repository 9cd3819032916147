#pragma once

#include <cstdint>

namespace cc {

constexpr uint32_t kVersionMajor = 0;
constexpr uint32_t kVersionMinor = 1;
constexpr uint32_t kVersionPatch = 0;

/// The version the library was built as, (major << 16) | (minor << 8) | patch, so a host can check
/// that headers and library agree: getVersion() == kVersion.
uint32_t getVersion();
constexpr uint32_t kVersion = (kVersionMajor << 16) | (kVersionMinor << 8) | kVersionPatch;

} // namespace cc
