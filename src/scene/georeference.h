#pragma once
// Placing a volume on the Earth: world (volume_frame.h, metres) <-> longitude/latitude, the
// footprint's corners, grid-north vs true-north, the manual lon/lat offset of Nes 2008 §5.5.1, and
// Earth-centred (ECEF) coordinates for the globe view.
//
// Datum choice: the lon/lat are those of the projection's own sphere, used as-is as WGS84 lon/lat
// for the basemap (Blue Marble is a plate carrée in WGS84 lon/lat); see geo/map_projection.h.
//
// World -> lon/lat: projected = (x0 − dx/2 + x_world, y0 − dy/2 + y_world) for metric grids (world
// 0 is the outer corner of cell (0, 0)); for geographic grids the local equirectangular scaling of
// frameOf() is undone first (degrees = metres / (R·π/180·cos φ_c)), then PROJ inverts rotated-pole
// grids. Finally the manual offset is added: lon/lat_shown = lon/lat_data + offset (Nes §5.5.1:
// "it is required to be able to fine tune the positioning").
//
// Not thread-safe (one PROJ context per object): give each thread its own SceneGeoreference.
#include <array>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "geo/grid_georeference.h"
#include "geo/map_projection.h"
#include "scene/camera.h"
#include "scene/sun.h"
#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::scene {

using geo::LonLat;
using geo::MapProjection;
using geo::normaliseLongitude_deg;

/// Manual placement correction (Nes 2008 §5.5.1), added to the data's lon/lat.
struct LonLatOffset {
  double lon_deg = 0.0;
  double lat_deg = 0.0;
};

class SceneGeoreference {
 public:
  /// From the grid's georeference. Cartesian grids (empty proj_definition, idealised runs) have no
  /// place on Earth: pass `centre_if_cartesian` to put the footprint's centre at that lon/lat with
  /// an azimuthal equidistant projection on WRF's sphere; without it they throw InputError.
  SceneGeoreference(const geo::GridGeoreference& grid, const volume::VolumeFrame& frame, LonLatOffset offset = {},
                    std::optional<LonLat> centre_if_cartesian = std::nullopt);
  SceneGeoreference(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, LonLatOffset offset = {},
                    std::optional<LonLat> centre_if_cartesian = std::nullopt)
      : SceneGeoreference(volumes.georef, frame, offset, centre_if_cartesian) {}

  /// World x/y [m] -> lon/lat (offset applied). Throws InputError where PROJ cannot invert.
  LonLat lonLatFromWorld(glm::dvec2 world_xy_m) const;
  /// lon/lat (as shown, offset included) -> world x/y [m].
  glm::dvec2 worldFromLonLat(LonLat ll) const;
  /// Batch version of lonLatFromWorld: xy interleaved in, lon/lat interleaved out (NaN on failure).
  void lonLatFromWorldBatch(double* xy_inout, std::size_t n) const;

  /// Footprint corners [0, size.x] × [0, size.y] in the order SW, SE, NE, NW (of the grid).
  std::array<LonLat, 4> footprintCorners() const;
  LonLat footprintCentre() const;
  /// Bounding box of the footprint's edges (sampled, not only corners: Lambert edges are curved).
  void footprintBounds(LonLat& min, LonLat& max) const;

  /// Angle [deg] from the world +y axis (grid north) clockwise to true north at `world_xy_m`
  /// (Lambert conformal: the meridian convergence n·(λ − λ0)).
  double trueNorthClockwiseFromGridNorth_deg(glm::dvec2 world_xy_m) const;
  /// A geographic sun (azimuth from true north) turned into the world frame at `world_xy_m`
  /// (azimuth from grid north), so that Sun::toSun() is right in world coordinates.
  Sun sunInWorld(const Sun& geographic, glm::dvec2 world_xy_m) const;

  /// Globe view: world point (x, y, z above sea level) -> Earth-centred coordinates [m] on the
  /// sphere of radius kEarthRadius_m (volume_frame.h).
  glm::dvec3 ecefFromWorld(const glm::dvec3& world_m) const;

  const volume::VolumeFrame& frame() const { return frame_; }
  LonLatOffset offset() const { return offset_; }
  const MapProjection& projection() const { return projection_; }

 private:
  glm::dvec2 projectedFromWorld(glm::dvec2 w) const;
  glm::dvec2 worldFromProjected(glm::dvec2 p) const;

  volume::VolumeFrame frame_;
  LonLatOffset offset_;
  MapProjection projection_;
  glm::dvec2 origin_{0.0};  ///< projected coordinates of world (0, 0)
  glm::dvec2 scale_{1.0};   ///< projected units per world metre (x, y)
};

/// Globe: Earth-centred, Earth-fixed coordinates [m] of lon/lat at height h above a sphere of
/// radius `radius_m` (x towards lon 0 on the equator, y towards lon 90°E, z towards the north pole).
glm::dvec3 ecefFromLonLat(LonLat ll, double height_m = 0.0, double radius_m = volume::kEarthRadius_m);
LonLat lonLatFromEcef(const glm::dvec3& ecef_m);
/// Local east, north, up unit vectors at lon/lat (columns of the ECEF-from-ENU rotation).
glm::dmat3 ecefFromEnu(LonLat ll);

/// Globe view: a flat-map camera (world frame) carried onto the sphere — position and target
/// through ecefFromWorld, up as the image of a short step along the flat up vector at the target —
/// so that the flat presets (scene_file.h) frame the same storm on the globe.
Camera globeCameraFrom(const Camera& flat, const SceneGeoreference& geo);

/// Globe view: ECEF unit vector towards a sun given in the *world* frame (azimuth from grid
/// north, as SceneGeoreference::sunInWorld returns it) at the footprint point `world_xy_m`.
glm::dvec3 toSunEcef(const Sun& world_sun, const SceneGeoreference& geo, glm::dvec2 world_xy_m);

}  // namespace nph::scene
