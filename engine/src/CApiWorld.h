#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"

/// The C handle: the C++ world plus the strings the C API hands out. Internal: shared with the
/// optional import library's C functions (crowdcloth_import.h), which add bodies to it.
struct cc_world {
    cc::World* world = nullptr;
    std::string lastError;
    std::string json;
    std::vector<uint8_t> snapshot;  ///< cc_world_save_state's bytes
};

namespace cc::detail {

// Exported for the import library only (crowdcloth_import.h), which is a library of its own.
CC_API cc_status toCStatus(StatusCode code);
/// Records the status as the world's last error (or clears it) and returns its C code.
CC_API cc_status reportToC(const cc_world* world, const Status& status);

/// Why a desc's version stamp is refused ("" when it is this library's layout), naming the desc
/// and its init function. The stamp is the first field of every layout, so it can be read
/// whatever headers the host was built with.
CC_API std::string stampError(const char* name, const char* init, uint32_t stamp);

} // namespace cc::detail
