#pragma once
// The horizontal georeference of a model's native grid: written once by the loaders (io/), carried
// by the extinction volumes and stored in the .nph cache (cache/), placed on the Earth by the
// scene (scene/georeference.h). One type for all of them, so nothing copies it field by field.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "geo/map_projection.h"

namespace nph::geo {

struct GridGeoreference {
  /// PROJ definition of the map projection ("+proj=lcc ... +R=6370000", a PROJ string without
  /// +type=crs); empty for Cartesian (idealized) runs without geolocation.
  std::string proj_definition;
  double dx_m = 0.0;  ///< grid spacing in projection units (degrees when `geographic`)
  double dy_m = 0.0;
  /// Projected coordinates of the centre of mass point (0, 0) in the units of proj_definition.
  double x0 = 0.0;
  double y0 = 0.0;
  /// true when x/y are longitude/latitude in degrees (regular lat-lon and rotated-pole grids).
  bool geographic = false;
  /// Geolocation of mass points from the file (XLAT/XLONG, lat/lon), nx*ny each, may be empty.
  std::vector<float> lat_deg;
  std::vector<float> lon_deg;

  bool operator==(const GridGeoreference&) const = default;

  /// Projected coordinates of mass point (i, j) (fractional indices allowed).
  glm::dvec2 projectedAt(double i, double j) const { return {x0 + i * dx_m, y0 + j * dy_m}; }
};

/// Longitude/latitude of mass point (i, j) of a georeferenced grid, `projection` being
/// MapProjection(georef.proj_definition). InputError where PROJ cannot invert the point.
LonLat gridLonLat(const MapProjection& projection, const GridGeoreference& georef, double i, double j);

}  // namespace nph::geo
