#pragma once
// Value checks shared by the loaders: every bad value is either repaired and counted (negative
// mixing ratios, missing condensate) or rejected with an InputError naming file and variable.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nph::io {

/// Throws InputError naming `var` and the first offending index unless every value is finite.
void requireFinite(const std::string& path, const std::string& var, const std::vector<float>& data);
/// Throws InputError unless every value lies in [lo, hi] (`what` says what the range means).
void requireRange(const std::string& path, const std::string& var, const std::vector<float>& data,
                  double lo, double hi, const std::string& what);
/// Sets negative values to 0; returns how many there were.
std::int64_t clampNegative(std::vector<float>& data);
/// Throws InputError when `fields` arrays of `points` floats exceed the memory budget.
void requireWithinBudget(const std::string& path, const std::string& what, double points, int fields,
                         std::size_t budget_bytes);

}  // namespace nph::io
