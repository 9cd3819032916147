#pragma once
// JSON as the crowd sample writes it for people to read: indented, with arrays of numbers (vectors,
// per-level counts) kept on one line.

#include <string>

#include <nlohmann/json.hpp>

namespace crowd {

std::string prettyJson(const nlohmann::ordered_json& value);

} // namespace crowd
