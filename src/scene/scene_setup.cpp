#include "scene/scene_setup.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/log.h"
#include "scene/basemap_cache.h"
#include "scene/dem.h"
#include "scene/night_lights.h"
#include "scene/solar_position.h"

namespace nph::scene {

std::size_t timestepIndexFor(const DataSpec& data, const std::vector<geo::OptionalUtcTime>& times,
                             const std::string& file) {
  if (times.empty()) throw InputError(fmt::format("{}: has no timesteps", file));
  if (!data.time_utc) {
    if (data.timestep < 0 || std::size_t(data.timestep) >= times.size()) {
      throw InputError(fmt::format("{}: timestep {} requested, the file has {} (0 to {})", file, data.timestep,
                                   times.size(), times.size() - 1));
    }
    return std::size_t(data.timestep);
  }
  constexpr double kSameTime_days = 1.0 / 86400.0;  // one second
  const double wanted = UtcTime::parse(*data.time_utc).julian_day;
  for (std::size_t t = 0; t < times.size(); ++t) {
    if (times[t] && std::abs(times[t]->julian_day - wanted) < kSameTime_days) return t;
  }
  throw InputError(fmt::format("{}: no timestep at {} (the file has {} timesteps, {} to {})", file, *data.time_utc,
                               times.size(), geo::isoOrEmpty(times.front()), geo::isoOrEmpty(times.back())));
}

WorldRect farBasemapRectangle(const volume::VolumeFrame& frame) {
  const glm::dvec3 size = frame.size_m();
  const double half = std::max(2.0e6, 3.0 * std::max(size.x, size.y));
  const glm::dvec2 centre{0.5 * size.x, 0.5 * size.y};
  return {centre - glm::dvec2(half), centre + glm::dvec2(half)};
}

PreparedScene prepareScene(const SceneDescription& s, const ExtinctionVolumes& v) {
  PreparedScene p;
  p.frame = volume::frameOf(v, s.height_exaggeration);
  if (!v.georef.proj_definition.empty() || s.centre_if_cartesian) {
    p.geo.emplace(v, p.frame, s.lonlat_offset, s.centre_if_cartesian);
  }
  const SceneGeoreference* geo = p.geo ? &*p.geo : nullptr;
  p.flat_camera = cameraFor(s.camera, p.frame, s.output.width, s.output.height);
  p.camera = p.flat_camera;
  p.sun = sunFor(s.sun, geo, v.time_utc);
  const glm::dvec3 size = p.frame.size_m();
  const glm::dvec2 centre{0.5 * size.x, 0.5 * size.y};
  if (s.view == ViewMode::Globe) {
    if (!geo) {
      throw InputError(fmt::format("{}: view \"globe\" needs the volume's place on Earth; its grid is "
                                   "Cartesian: give centre_lonlat_deg",
                                   s.source_file));
    }
    p.camera = globeCameraFrom(p.flat_camera, *geo);
    p.to_sun_ecef = toSunEcef(p.sun, *geo, centre);
  }
  if (s.terrain && !s.terrain->dem.empty()) {
    if (!geo) {
      throw InputError(fmt::format("{}: terrain.dem: the volume's grid is Cartesian (no map projection): "
                                   "give centre_lonlat_deg to place it on the map",
                                   s.source_file));
    }
    // The far field only for the flat view: the globe's terrain ends with its table (docs/terrain.md).
    // On a lattice as fine as the DEM's own pixels (up to 8x the model's): its ridges and valleys.
    const DemRaster raster = DemRaster::open(s.terrain->dem);
    p.dem = demHeightsFor(raster, *geo, p.frame, s.view == ViewMode::Flat, demRefinementFor(raster, *geo, p.frame));
  }
  if (s.basemap) {
    if (!geo) {
      throw InputError(fmt::format("{}: basemap: the volume's grid is Cartesian (no map projection): "
                                   "give centre_lonlat_deg to place it on the map",
                                   s.source_file));
    }
    const WorldRect rect = basemapRectangle(p.frame, s.basemap->margin);
    const glm::dvec2 extent = rect.max_m - rect.min_m;
    const double longSide = std::max(extent.x, extent.y);
    const int n = s.basemap->pixels_long_side;
    const int w = std::max(1, static_cast<int>(std::lround(n * extent.x / longSide)));
    const int h = std::max(1, static_cast<int>(std::lround(n * extent.y / longSide)));
    // Issue 14 item 3: any GDAL raster. A regional one lies over the whole-Earth default where the
    // default is installed, so the margin, the far ground and the globe are not black around it.
    std::vector<BasemapRaster> layers{BasemapRaster::open(s.basemap->path)};
    if (!layers.front().wholeEarth() && std::filesystem::exists(kBlueMarblePath)) {
      layers.insert(layers.begin(), BasemapRaster::open(kBlueMarblePath));
    }
    p.basemap = reprojectBasemapCached(layers, *geo, rect, w, h);
    // The night side's lights on the same grids (issue 14): the scene's raster, else Debian's.
    std::optional<BasemapRaster> lights;
    if (s.style.city_lights > 0.0) {
      if (!s.basemap->night_lights.empty()) {
        lights = BasemapRaster::open(s.basemap->night_lights);
      } else if (std::filesystem::exists(kCityLightsPath)) {
        lights = BasemapRaster::open(kCityLightsPath);
      }
    }
    if (lights) p.basemap_lights = cityLightsIntensity(reprojectBasemapCached({*lights}, *geo, rect, w, h));
    if (s.view == ViewMode::Globe) {
      const glm::ivec2 globeSize = equirectangularSizeFor(layers.back());
      p.basemap_equirect = reprojectEquirectangularCached(layers, globeSize.x, globeSize.y);
      if (lights) {
        p.basemap_equirect_lights =
            cityLightsIntensity(reprojectEquirectangularCached({*lights}, globeSize.x, globeSize.y));
      }
    } else {
      p.far_basemap_rect = farBasemapRectangle(p.frame);
      p.far_basemap = reprojectBasemapCached(layers, *geo, *p.far_basemap_rect, kFarBasemapPixels, kFarBasemapPixels);
      if (lights) {
        p.far_basemap_lights = cityLightsIntensity(
            reprojectBasemapCached({*lights}, *geo, *p.far_basemap_rect, kFarBasemapPixels, kFarBasemapPixels));
      }
    }
    p.basemap_rect = rect;
    log::info("basemap {}: {}x{} pixels over {:.0f}x{:.0f} km", s.basemap->path, w, h, extent.x / 1000.0,
              extent.y / 1000.0);
  }
  return p;
}

}  // namespace nph::scene
