#pragma once

#include <string>

#include "crowdcloth/character/Character.h"

namespace cc::detail {

/// A character as bytes, to carry an import out of the child process that parsed the file
/// (IsolatedImport). Same binary on both ends: native byte order, doubles as they are.
std::string serializeCharacter(const Character& character);

/// Reads serializeCharacter()'s bytes back; every count is checked against what is left, so a
/// cut or corrupt blob gives an error, never a crash.
Result<Character> deserializeCharacter(const std::string& bytes);

} // namespace cc::detail
