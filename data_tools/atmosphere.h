#pragma once
// Analytic atmosphere shared by the generators: the 1976 U.S. Standard Atmosphere (identical to
// the ICAO standard atmosphere below 32 km), saturation vapour pressure and deterministic noise.
// Heights are treated as geometric heights (the geopotential/geometric difference, < 0.3 % below
// 20 km, does not matter for synthetic scenes).
#include <cstdint>

namespace nph::datagen {

/// Standard gravity [m/s^2], U.S. Standard Atmosphere 1976, table 2.
inline constexpr double kStdGravity_m_per_s2 = 9.80665;
/// Specific gas constant of dry air used by the U.S. Standard Atmosphere 1976 [J/(kg K)]
/// (R* / M0 = 8.31432 / 0.0289644).
inline constexpr double kStdGasConstantDryAir_J_per_kgK = 287.0531;
/// Sea-level pressure [Pa] and temperature [K] of the standard atmosphere.
inline constexpr double kStdSeaLevelPressure_pa = 101325.0;
inline constexpr double kStdSeaLevelTemperature_k = 288.15;
/// 0 °C in kelvin.
inline constexpr double kFreezingPoint_k = 273.15;

/// Standard-atmosphere temperature [K] at height z [m] (valid 0 .. 32 km, clamped outside).
double standardTemperatureK(double height_m);
/// Standard-atmosphere pressure [Pa] at height z [m] (hydrostatic, valid -500 m .. 32 km).
double standardPressurePa(double height_m);
/// Inverse of standardPressurePa: height [m] of pressure p [Pa] (868 Pa .. 107 kPa).
double standardHeightM(double pressure_pa);

/// Saturation vapour pressure over liquid water [Pa] (Bolton 1980, eq. 10), T in K.
double saturationVapourPressurePa(double temperature_k);

/// Deterministic value noise in [0, 1) on the integer lattice, smoothly interpolated.
class ValueNoise {
 public:
  explicit ValueNoise(std::uint64_t seed) : seed_(seed) {}
  /// Smooth noise at (x, y, z) in lattice units, in [0, 1).
  double at(double x, double y, double z) const;
  /// Fractional Brownian motion: `octaves` octaves, lacunarity 2, gain 0.5, normalised to [0, 1).
  double fbm(double x, double y, double z, int octaves) const;
  /// Uniform random number in [0, 1) from integer coordinates (hash, no smoothing).
  double hash(std::int64_t a, std::int64_t b, std::int64_t c) const;

 private:
  std::uint64_t seed_;
};

}  // namespace nph::datagen
