#pragma once
// Physical constants of the optics stage, SI units, each with its source.
namespace nph::physics {

/// Gas constant of dry air [J/(kg K)] (Muth 2026 §3.3.1, eq. 3.2).
inline constexpr double kGasConstantDryAir = 287.05;
/// Gas constant of water vapour [J/(kg K)] (Muth 2026 §3.3.1).
inline constexpr double kGasConstantVapour = 461.5;
/// ε = R_d / R_v ≈ 0.622: ratio of the molar masses of water and dry air.
inline constexpr double kEpsilon = kGasConstantDryAir / kGasConstantVapour;
/// Melting point [K]; WSM3 (Hong et al. 2004) separates cloud water/ice and rain/snow here.
inline constexpr double kFreezingPointK = 273.15;
/// Density of liquid water [kg/m³] (Muth 2026 §3.3.1, eq. 3.4).
inline constexpr double kDensityWater = 1000.0;
/// Density of solid ice [kg/m³] (Muth 2026 §3.3.1, eq. 3.4; Pruppacher & Klett 1997).
inline constexpr double kDensityIce = 917.0;
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace nph::physics
