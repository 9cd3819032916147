#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "crowdcloth/character/Character.h"

namespace cc::detail {

/// Runs `read` in a child process and brings its character back through a pipe: a parser that
/// crashes, hangs longer than `timeoutSeconds` or needs more than `memoryBytes` of address space
/// (0 = no cap) costs an error naming the file, never the host. Where no child process can be
/// made, `read` runs in this process.
Result<Character> readIsolated(const std::function<Result<Character>()>& read, const std::string& path,
                               double timeoutSeconds, std::size_t memoryBytes);

} // namespace cc::detail
