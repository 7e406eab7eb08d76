// Solar position (NOAA / Meeus ch. 25) against published reference values.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "scene/solar_position.h"

namespace nph::scene {
namespace {

// Stated accuracy of the algorithm (header): about 0.01°; tests allow 0.02° against references
// that are themselves exact to better than 0.001°.
constexpr double kAccuracy_deg = 0.02;

TEST(SolarPosition, NrelSpaReferenceCase) {
  // Reda & Andreas (2004), NREL/TP-560-34302, appendix A.5: 2003-10-17 12:30:30 local time,
  // time zone −7, lat 39.742476°, lon −105.1786°, 820 hPa, 11 °C. Published topocentric zenith
  // 50.11162° (refracted) and azimuth 194.34024° (eastward from north).
  const UtcTime t = UtcTime::parse("2003-10-17T12:30:30-07:00");
  EXPECT_EQ(t.iso8601(), "2003-10-17T19:30:30Z");
  const SolarPosition p = solarPosition(t, -105.1786, 39.742476);
  const double refracted = p.elevation_deg + refractionCorrection_deg(p.elevation_deg, 820.0, 11.0);
  EXPECT_NEAR(90.0 - refracted, 50.11162, kAccuracy_deg);
  EXPECT_NEAR(p.azimuth_deg, 194.34024, kAccuracy_deg);
  // SPA's intermediate geocentric declination δ = −9.31434°.
  EXPECT_NEAR(p.declination_deg, -9.31434, kAccuracy_deg);
}

TEST(SolarPosition, MeeusExample25a) {
  // Meeus (1998) example 25.a, 1992 October 13.0 (JD 2448908.5), low-accuracy method:
  // apparent λ = 199.90895°, α = 198.38083°, δ = −7.78507°, R = 0.99766 AU.
  const SolarCoordinates c = solarCoordinates(UtcTime{2448908.5});
  EXPECT_NEAR(c.apparent_longitude_deg, 199.90895, 1e-3);
  EXPECT_NEAR(c.right_ascension_deg, 198.38083, 1e-3);
  EXPECT_NEAR(c.declination_deg, -7.78507, 1e-3);
  EXPECT_NEAR(c.earth_sun_distance_au, 0.99766, 1e-4);
  EXPECT_EQ(UtcTime::fromCivil(1992, 10, 13).julian_day, 2448908.5);
}

TEST(SolarPosition, SolsticesAndEquinox) {
  // 2026 solstices/equinox (USNO): Mar 20 14:46, Jun 21 08:24, Dec 21 20:50 UTC. Obliquity 23.436°.
  EXPECT_NEAR(solarCoordinates(UtcTime::parse("2026-03-20T14:46:00Z")).declination_deg, 0.0, 0.01);
  EXPECT_NEAR(solarCoordinates(UtcTime::parse("2026-06-21T08:24:00Z")).declination_deg, 23.436, 0.01);
  EXPECT_NEAR(solarCoordinates(UtcTime::parse("2026-12-21T20:50:00Z")).declination_deg, -23.436, 0.01);
  // A day either side the declination is lower in magnitude (a maximum, not a zero crossing).
  EXPECT_LT(solarCoordinates(UtcTime::parse("2026-06-20T08:24:00Z")).declination_deg, 23.436);
  EXPECT_LT(solarCoordinates(UtcTime::parse("2026-06-22T08:24:00Z")).declination_deg, 23.436);
}

TEST(SolarPosition, NoonElevationAndSubsolarPoint) {
  const UtcTime t = UtcTime::parse("2026-06-21T08:24:00Z");
  double lon = 0, lat = 0;
  subsolarPoint(t, lon, lat);
  EXPECT_NEAR(lat, 23.436, 0.01);
  // 08:24 UTC, equation of time ≈ −1.8 min: the sun culminates at (720 − 504 + 1.8)/4 ≈ 54.4°E.
  EXPECT_NEAR(lon, 180.0 - 8.4 * 15.0 - (-1.8 / 4.0), 0.1);
  EXPECT_NEAR(solarPosition(t, lon, lat).elevation_deg, 90.0, 1e-6);
  // Local solar noon at 50°N on the meridian of the subsolar point: elevation 90 − 50 + δ, due south.
  const SolarPosition noon = solarPosition(t, lon, 50.0);
  EXPECT_NEAR(noon.elevation_deg, 90.0 - 50.0 + 23.436, kAccuracy_deg);
  EXPECT_NEAR(noon.azimuth_deg, 180.0, 1e-6);
  EXPECT_NEAR(noon.hour_angle_deg, 0.0, 1e-9);
  // South of the subsolar latitude the noon sun stands in the north.
  EXPECT_NEAR(solarPosition(t, lon, -30.0).azimuth_deg, 0.0, 1e-6);
  // Antipode: sun at the nadir.
  EXPECT_NEAR(solarPosition(t, lon + 180.0, -lat).elevation_deg, -90.0, 1e-6);
  // Six hours later the sun is 90° west of the subsolar meridian, on the horizon at the equator
  // (to the sphere-geometry accuracy of a few hundredths of a degree, EoT changes slowly).
  const UtcTime later{t.julian_day + 0.25};
  EXPECT_NEAR(solarPosition(later, lon, 0.0).elevation_deg, 0.0, 0.05);
}

TEST(SolarPosition, EquationOfTimeExtremes) {
  // Published extremes: about +16.4 min near 3 November, about −14.2 min near 11 February.
  EXPECT_NEAR(solarCoordinates(UtcTime::parse("2026-11-03T12:00:00Z")).equation_of_time_min, 16.4, 0.15);
  EXPECT_NEAR(solarCoordinates(UtcTime::parse("2026-02-11T12:00:00Z")).equation_of_time_min, -14.2, 0.15);
}

TEST(SolarPosition, MorningSunIsInTheEast) {
  // Hamburg, 1 September 2026, 06:00 UTC (08:00 CEST): sun low in the east.
  const SolarPosition p = solarPosition(UtcTime::parse("2026-09-01T06:00:00Z"), 10.0, 53.55);
  EXPECT_GT(p.azimuth_deg, 70.0);
  EXPECT_LT(p.azimuth_deg, 110.0);
  EXPECT_GT(p.elevation_deg, 5.0);
  EXPECT_LT(p.elevation_deg, 25.0);
  const Sun s = sunAt(UtcTime::parse("2026-09-01T06:00:00Z"), 10.0, 53.55);
  EXPECT_GT(s.toSun().x, 0.5);  // x = east in the world frame
  EXPECT_NEAR(s.elevation_deg, p.elevation_deg, 1e-12);
}

TEST(SolarPosition, Refraction) {
  // Bennett/SPA: about 0.48° at the horizon (1010 hPa, 10 °C), 0.016° at 45°, none below −0.8°.
  EXPECT_NEAR(refractionCorrection_deg(0.0), 0.48, 0.02);
  EXPECT_NEAR(refractionCorrection_deg(45.0), 0.0166, 0.001);
  EXPECT_EQ(refractionCorrection_deg(-5.0), 0.0);
  const UtcTime t = UtcTime::parse("2026-09-01T06:00:00Z");
  EXPECT_GT(solarPosition(t, 10.0, 53.55, true).elevation_deg, solarPosition(t, 10.0, 53.55).elevation_deg);
}

}  // namespace
}  // namespace nph::scene
