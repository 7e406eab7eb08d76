#pragma once
// The one wrapper of PROJ in nephele: a map projection of a model grid ("+proj=lcc ... +R=6370000",
// as the loaders write it into GridGeoreference::proj_definition) against longitude/latitude.
// Used by the loaders (WRF origin and XLAT/XLONG checks), the scene placement (scene/georeference.h)
// and the sample-data generators.
//
// Datum choice. WRF (and WPS) compute on a sphere of radius 6 370 000 m and feed it WGS84 latitudes
// and longitudes unchanged; ICON does the same on its 6 371 229 m sphere. The model's lon/lat are
// therefore *numerically* WGS84 lon/lat (a geodetic latitude used as a spherical one). nephele
// follows this convention: the transformation goes between the data's projection and lon/lat on
// the projection's own sphere or ellipsoid (the +R/+a/+b/+rf/+f/+ellps/+datum terms of the
// definition; WGS84 when it names none), with no datum shift. Converting "sphere lat -> WGS84 lat"
// as a datum change instead would move features by up to ~21 km (0.19° at 45°N) against where the
// model put them, which is exactly the misplacement Nes 2008 §5.5.1 fixes by hand.
//
// Not thread-safe (one PROJ context per object): give each thread its own MapProjection.
#include <cstddef>
#include <memory>
#include <string>

#include <glm/glm.hpp>

namespace nph::geo {

struct LonLat {
  double lon_deg = 0.0;  ///< east positive, (-180, 180] after normalisation
  double lat_deg = 0.0;
};

/// Longitude wrapped to (-180, 180].
double normaliseLongitude_deg(double lon_deg);

/// A PROJ transformation between a projection (a PROJ string without +type=crs) and lon/lat on
/// the projection's own sphere or ellipsoid (degrees, lon first). Move-only.
class MapProjection {
 public:
  /// InputError naming the definition when PROJ cannot use it (an empty definition included).
  explicit MapProjection(const std::string& proj_definition);
  ~MapProjection();
  MapProjection(MapProjection&&) noexcept;
  MapProjection& operator=(MapProjection&&) noexcept;
  MapProjection(const MapProjection&) = delete;
  MapProjection& operator=(const MapProjection&) = delete;

  /// lon/lat -> projected (metres, or degrees for longlat/rotated grids). InputError naming the
  /// definition and the point where PROJ cannot project it.
  glm::dvec2 forward(LonLat ll) const;
  /// projected -> lon/lat. InputError where PROJ cannot invert (or gives |lat| > 90°).
  LonLat inverse(glm::dvec2 xy) const;
  /// In-place batch inverse of n points (x, y interleaved); unprojectable points become NaN.
  void inverseBatch(double* xy, std::size_t n) const;
  const std::string& definition() const { return definition_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string definition_;
};

}  // namespace nph::geo
