#pragma once
// Environment variable access (std::getenv wrapped so callers get std::optional).
#include <optional>
#include <string>

namespace nph::env {

/// The value of `name`, or nullopt when unset or empty.
std::optional<std::string> get(const char* name);

}  // namespace nph::env
