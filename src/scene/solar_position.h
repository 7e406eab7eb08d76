#pragma once
// Where the sun stands in the sky for a UTC instant and a place on Earth.
//
// Algorithm: NOAA Global Monitoring Laboratory's solar calculator (the "NOAA_Solar_Calculations"
// spreadsheet), which implements the low-accuracy solar coordinates of Meeus, *Astronomical
// Algorithms* (2nd ed., 1998), ch. 25 ("Solar Coordinates", eq. 25.2-25.8 and the equation of
// time of ch. 28, eq. 28.3). Meeus states an accuracy of 0.01° for the sun's apparent longitude
// with these series; declination, right ascension and hence azimuth/elevation are good to about
// 0.01° for years 1900-2100 (tested below 0.02° against the NREL SPA reference case, Reda &
// Andreas 2004, whose own uncertainty is ±0.0003°). ΔT (TT − UT, ~1 min) is ignored: its effect on
// the sun's longitude is < 0.001°. Parallax (≤ 0.0024°) is ignored.
//
// Elevation is geometric (no atmospheric refraction) unless `refracted` is requested: light is
// rendered along straight rays, so the geometric direction is what the renderer wants; the
// refraction correction (≤ 0.6° at the horizon) is offered for comparison with almanacs.
#include <string>
#include <string_view>

#include "geo/utc_time.h"
#include "scene/sun.h"

namespace nph::scene {

/// A UTC instant; the solar position reads its Julian Day (UT).
using geo::UtcTime;

struct SolarCoordinates {
  double declination_deg = 0.0;         ///< apparent declination δ
  double right_ascension_deg = 0.0;     ///< apparent right ascension α, [0, 360)
  double equation_of_time_min = 0.0;    ///< apparent − mean solar time [minutes]
  double apparent_longitude_deg = 0.0;  ///< λ, [0, 360)
  double earth_sun_distance_au = 1.0;   ///< R
};

/// Sun's apparent geocentric coordinates at `time` (Meeus ch. 25, low accuracy; NOAA).
SolarCoordinates solarCoordinates(const UtcTime& time);

struct SolarPosition {
  double azimuth_deg = 0.0;     ///< clockwise from geographic north, [0, 360)
  double elevation_deg = 0.0;   ///< above the horizon; geometric unless refracted
  double hour_angle_deg = 0.0;  ///< local hour angle, (-180, 180], 0 at local solar noon
  double declination_deg = 0.0;
};

/// Azimuth and elevation of the sun seen from (lon, lat) at `time`. Longitude east positive.
SolarPosition solarPosition(const UtcTime& time, double lon_deg, double lat_deg, bool refracted = false);

/// Atmospheric refraction added to a geometric elevation [deg] (NREL SPA, Reda & Andreas 2004,
/// eq. 42, after Bennett's formula), for pressure [hPa] and temperature [°C]; 0 below −0.8°.
double refractionCorrection_deg(double geometric_elevation_deg, double pressure_hPa = 1010.0,
                                double temperature_C = 10.0);

/// The point where the sun is at the zenith: latitude = declination, longitude from the
/// Greenwich hour angle (east positive, (-180, 180]).
void subsolarPoint(const UtcTime& time, double& lon_deg, double& lat_deg);

/// Unit vector from the Earth's centre towards the sun (ECEF axes of georeference.h: x to lon 0
/// on the equator, z to the north pole); the sun is at infinity, so this is also the direction
/// to the sun from any point (parallax < 0.0024°). For the globe view.
glm::dvec3 sunDirectionEcef(const UtcTime& time);

/// A scene::Sun pointing at the sun's position (colour and intensity left at their defaults).
Sun sunAt(const UtcTime& time, double lon_deg, double lat_deg);

}  // namespace nph::scene
