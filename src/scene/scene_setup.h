#pragma once
// From a parsed scene file and the volumes of its timestep to everything a renderer draws with:
// the volume's frame, its place on Earth, the camera and sun in the render's frame, and the
// basemap already reprojected under the footprint. One call for `nephele render` and the viewer,
// so GPU renderer and CPU references set a scene up the same way.
#include <optional>
#include <string>
#include <vector>

#include "scene/basemap.h"
#include "scene/camera.h"
#include "scene/georeference.h"
#include "scene/scene_file.h"
#include "scene/sun.h"
#include "volume/extinction_volumes.h"
#include "volume/terrain_field.h"
#include "volume/volume_frame.h"

namespace nph::scene {

/// Index of the timestep `data` asks for among `times_utc` (the file's times, ISO 8601 or WRF):
/// data.time_utc must match one to within a second; otherwise data.timestep must be in range.
/// InputError names `file`, what was asked and what the file has.
std::size_t timestepIndexFor(const DataSpec& data, const std::vector<geo::OptionalUtcTime>& times,
                             const std::string& file);

struct PreparedScene {
  volume::VolumeFrame frame;
  std::optional<SceneGeoreference> geo;   ///< none for Cartesian grids without centre_lonlat_deg
  Camera flat_camera;                     ///< world frame (volume_frame.h)
  Camera camera;                          ///< = flat_camera, or carried onto the globe (ECEF)
  Sun sun;                                ///< world frame: azimuth from grid north
  std::optional<glm::dvec3> to_sun_ecef;  ///< globe: direction to the sun (needs geo)
  std::optional<WorldRect> basemap_rect;  ///< world rectangle the basemap covers
  LinearRgbImage basemap;                 ///< reprojected linear RGB (empty without a basemap)
  LinearRgbImage basemap_equirect;        ///< globe: the whole source image by lon/lat (else empty)
  /// Flat view (issue 14 item 4, no void): the same source reprojected, coarser, over a square of
  /// farBasemapRectangle() around the footprint, so the ground goes on to the horizon (where the
  /// atmosphere's aerial perspective fades it into the sky) instead of ending at the near one.
  std::optional<WorldRect> far_basemap_rect;
  LinearRgbImage far_basemap;
  /// The night side's city lights (issue 14; scene/night_lights.h cityLightsIntensity), one
  /// intensity per pixel of basemap, far_basemap and basemap_equirect; each empty where that image
  /// is, or when the style's city_lights is 0 or no lights raster is given nor installed.
  std::vector<float> basemap_lights, far_basemap_lights, basemap_equirect_lights;
  /// A user DEM (scene "terrain": {"dem": ...}; scene/dem.h) on the model's mass points and the far
  /// square, for render::VolumeTextures::upload; none without one.
  std::optional<volume::DemHeights> dem;
};

/// The far basemap's rectangle: the footprint's centre ± max(2000 km, 3 × its longer side). At
/// 2000 km the sea-level air's transmittance is below e^{−10} even in the red (Rayleigh + aerosol,
/// atmosphere/atmosphere.h), so ground further out is never seen through the atmosphere.
WorldRect farBasemapRectangle(const volume::VolumeFrame& frame);
/// Pixels on each side of the far basemap: 1024 (≈ 4 km each at 2000 km; Blue Marble has 15 km).
inline constexpr int kFarBasemapPixels = 1024;

/// Builds the scene. Throws InputError for what the scene asks but the data cannot give (a
/// basemap or a timed sun for a volume without a place on Earth, a missing basemap file, ...).
PreparedScene prepareScene(const SceneDescription& scene, const ExtinctionVolumes& volumes);

}  // namespace nph::scene
