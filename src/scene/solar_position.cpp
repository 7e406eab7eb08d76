#include "scene/solar_position.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/error.h"

namespace nph::scene {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kJ2000 = 2451545.0;  ///< JD of 2000-01-01T12:00:00 (TT ≈ UT here)
constexpr double kDaysPerJulianCentury = 36525.0;

double wrap360(double deg) {
  double r = std::fmod(deg, 360.0);
  return r < 0.0 ? r + 360.0 : r;
}
double wrap180(double deg) {  // (-180, 180]
  double r = wrap360(deg);
  return r > 180.0 ? r - 360.0 : r;
}

}  // namespace

// NOAA solar calculator = Meeus (1998) ch. 25, low accuracy. Symbols as in Meeus.
SolarCoordinates solarCoordinates(const UtcTime& time) {
  const double T = (time.julian_day - kJ2000) / kDaysPerJulianCentury;       // Julian centuries
  const double L0 = wrap360(280.46646 + T * (36000.76983 + T * 0.0003032));  // mean longitude, 25.2
  const double M = 357.52911 + T * (35999.05029 - T * 0.0001537);            // mean anomaly, 25.3
  const double e = 0.016708634 - T * (0.000042037 + T * 0.0000001267);       // eccentricity, 25.4
  const double Mr = M * kDeg;
  const double C = std::sin(Mr) * (1.914602 - T * (0.004817 + T * 0.000014)) +
                   std::sin(2.0 * Mr) * (0.019993 - T * 0.000101) +
                   std::sin(3.0 * Mr) * 0.000289;  // equation of centre
  const double trueLongitude = L0 + C;
  const double v = M + C;                                                         // true anomaly
  const double R = 1.000001018 * (1.0 - e * e) / (1.0 + e * std::cos(v * kDeg));  // 25.5
  const double omega = 125.04 - 1934.136 * T;  // longitude of the Moon's ascending node
  const double lambda = trueLongitude - 0.00569 - 0.00478 * std::sin(omega * kDeg);  // apparent
  const double eps0 = 23.0 + (26.0 + (21.448 - T * (46.8150 + T * (0.00059 - T * 0.001813))) / 60.0) / 60.0;  // 22.2
  const double eps = eps0 + 0.00256 * std::cos(omega * kDeg);  // corrected for apparent position
  const double lr = lambda * kDeg, er = eps * kDeg;
  SolarCoordinates c;
  c.apparent_longitude_deg = wrap360(lambda);
  c.right_ascension_deg = wrap360(std::atan2(std::cos(er) * std::sin(lr), std::cos(lr)) / kDeg);  // 25.6
  c.declination_deg = std::asin(std::sin(er) * std::sin(lr)) / kDeg;                              // 25.7
  c.earth_sun_distance_au = R;
  // Equation of time (Meeus eq. 28.3, Smart's series), in minutes of time (4 min per degree).
  const double y = std::pow(std::tan(er / 2.0), 2.0);
  const double L0r = L0 * kDeg;
  const double E = y * std::sin(2.0 * L0r) - 2.0 * e * std::sin(Mr) + 4.0 * e * y * std::sin(Mr) * std::cos(2.0 * L0r) -
                   0.5 * y * y * std::sin(4.0 * L0r) - 1.25 * e * e * std::sin(2.0 * Mr);
  c.equation_of_time_min = 4.0 * E / kDeg;
  return c;
}

SolarPosition solarPosition(const UtcTime& time, double lon_deg, double lat_deg, bool refracted) {
  if (!std::isfinite(lon_deg) || !std::isfinite(lat_deg) || std::abs(lat_deg) > 90.0) {
    throw UsageError(fmt::format("solarPosition: lon {} lat {} is not a place on Earth", lon_deg, lat_deg));
  }
  const SolarCoordinates c = solarCoordinates(time);
  // True solar time [min] = UTC minutes + equation of time + 4 min per degree east (NOAA).
  const double trueSolarTime_min = time.utcHourOfDay() * 60.0 + c.equation_of_time_min + 4.0 * lon_deg;
  const double H = wrap180(trueSolarTime_min / 4.0 - 180.0);  // hour angle, 0 at solar noon
  const double Hr = H * kDeg, phi = lat_deg * kDeg, d = c.declination_deg * kDeg;
  // Horizontal coordinates (Meeus eq. 13.5-13.6); azimuth from north = Meeus' (from south) + 180.
  const double sinElevation = std::sin(phi) * std::sin(d) + std::cos(phi) * std::cos(d) * std::cos(Hr);
  SolarPosition p;
  p.elevation_deg = std::asin(std::clamp(sinElevation, -1.0, 1.0)) / kDeg;
  p.azimuth_deg =
      wrap360(std::atan2(std::sin(Hr), std::cos(Hr) * std::sin(phi) - std::tan(d) * std::cos(phi)) / kDeg + 180.0);
  p.hour_angle_deg = H;
  p.declination_deg = c.declination_deg;
  if (refracted) p.elevation_deg += refractionCorrection_deg(p.elevation_deg);
  return p;
}

double refractionCorrection_deg(double e0, double pressure_hPa, double temperature_C) {
  // SPA eq. 42: Δe = (P/1010)·(283/(273+T))·1.02 / (60·tan(e0 + 10.3/(e0 + 5.11))) [degrees].
  constexpr double kBelowHorizonLimit_deg = -0.8;  // SPA applies it for e0 ≥ −(sun radius + refraction)
  if (e0 < kBelowHorizonLimit_deg) return 0.0;
  return (pressure_hPa / 1010.0) * (283.0 / (273.0 + temperature_C)) * 1.02 /
         (60.0 * std::tan((e0 + 10.3 / (e0 + 5.11)) * kDeg));
}

void subsolarPoint(const UtcTime& time, double& lon_deg, double& lat_deg) {
  const SolarCoordinates c = solarCoordinates(time);
  lat_deg = c.declination_deg;
  // Hour angle zero: UTC minutes + EoT + 4·lon = 720.
  lon_deg = wrap180((720.0 - time.utcHourOfDay() * 60.0 - c.equation_of_time_min) / 4.0);
}

glm::dvec3 sunDirectionEcef(const UtcTime& time) {
  double lon = 0.0, lat = 0.0;
  subsolarPoint(time, lon, lat);
  const double l = lon * kDeg, p = lat * kDeg;
  return {std::cos(p) * std::cos(l), std::cos(p) * std::sin(l), std::sin(p)};
}

Sun sunAt(const UtcTime& time, double lon_deg, double lat_deg) {
  const SolarPosition p = solarPosition(time, lon_deg, lat_deg);
  Sun s;
  s.azimuth_deg = p.azimuth_deg;
  s.elevation_deg = p.elevation_deg;
  return s;
}

}  // namespace nph::scene
