#pragma once
// Value checks shared by the loaders: every bad value is either repaired and counted (negative
// mixing ratios, missing condensate) or rejected with an InputError naming file and variable.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nph::io {

/// Plausibility gates for model fields (issue #18): values outside are not weather but broken
/// files, refused with the file, variable and range instead of rendering garbage.
/// Hydrometeor and vapour mixing ratios: the wettest hail cores hold ~0.03 kg/kg, saturation
/// vapour at 40 °C ~0.05 kg/kg; 0.1 kg/kg leaves room and stops 1e30 or unpacked shorts.
inline constexpr double kMaxMixingRatio_kg_per_kg = 0.1;
/// Number concentrations: polluted cloud droplets ~1e10 /kg; 1e13 /kg leaves three decades.
inline constexpr double kMaxNumberConcentration_per_kg = 1e13;
/// Heights: the Dead Sea shore lies at -430 m; model tops are below 100 km (MPAS up to 80 km).
inline constexpr double kLowestHeight_m = -1000.0;
inline constexpr double kHighestHeight_m = 2.0e5;
/// Terrain: Mount Everest, 8849 m.
inline constexpr double kHighestTerrain_m = 9000.0;

/// Throws InputError naming `var` and the first offending index unless every value is finite.
void requireFinite(const std::string& path, const std::string& var, const std::vector<float>& data);
/// Throws InputError unless every value lies in [lo, hi] (`what` says what the range means).
void requireRange(const std::string& path, const std::string& var, const std::vector<float>& data, double lo, double hi,
                  const std::string& what);
/// Throws InputError unless every value is <= hi (NaN included in the failures).
void requireAtMost(const std::string& path, const std::string& var, const std::vector<float>& data, double hi,
                   const std::string& what);
/// Sets negative values to 0; returns how many there were.
std::int64_t clampNegative(std::vector<float>& data);
/// Throws InputError when `fields` arrays of `points` floats exceed the memory budget.
void requireWithinBudget(const std::string& path, const std::string& what, double points, int fields,
                         std::size_t budget_bytes);

}  // namespace nph::io
