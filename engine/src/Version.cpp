#include "crowdcloth/Version.h"

namespace cc {

uint32_t getVersion() { return kVersion; }

} // namespace cc
