#pragma once
// A generated mountain range as a real GeoTIFF (issue 14: "terrain that reads as mountains"; no
// real DEM may be downloaded here, and no Debian package ships one: docs/terrain.md "A generated
// Alpine DEM"). Written through GDAL so that it enters nephele by the user-DEM path
// ("terrain": {"dem": FILE}, scene/dem.h) exactly as SRTM or Copernicus tiles would.
//
// The relief (Musgrave's ridged multifractal, Ebert et al. 2003 "Texturing & Modeling" §16.4,
// over a domain-warped lattice), inside an Alpine belt: a polyline along the real Alps' axis
// (Maritime Alps → Mont Blanc → Bernese Oberland → Hohe Tauern → Vienna), heights up to `peak_m`
// on the axis falling to a foreland of a few hundred metres and to sea level 250 km away. It is
// synthesis, not the Alps: the ridges are not the real ones; only the belt follows the real
// range, so that Blue Marble's snow and valleys lie roughly under it. Deterministic from `seed`.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nph::datagen {

struct DemSpec {
  double lon_min_deg = 3.0, lat_min_deg = 42.0;  ///< south-west corner (EPSG:4326)
  double lon_max_deg = 21.0, lat_max_deg = 51.0;
  double pixel_deg = 0.01;  ///< ≈ 0.76 km × 1.1 km at 47° N: finer than the models' 1–10 km
  double peak_m = 4000.0;   ///< the belt's ridges on its axis reach about this
  std::uint64_t seed = 1;
};

struct DemTruth {
  int width = 0, height = 0;
  double min_m = 0.0, max_m = 0.0;
};

/// Float32 GeoTIFF (deflate, EPSG:4326, unit "m", no nodata: the whole rectangle has heights).
/// Throws std::runtime_error naming `path` when GDAL cannot write it or the spec is empty.
DemTruth writeGeneratedDem(const DemSpec& spec, const std::string& path);

/// The height [m] the generator gives at (lon, lat): the same function the file samples at its
/// pixel centres (for tests).
double generatedDemHeight_m(const DemSpec& spec, double lon_deg, double lat_deg);

/// A Float32 GeoTIFF of heights [m] (deflate, unit "m", no nodata), row 0 first as `geotransform`
/// (GDAL's six coefficients) says, in `crs` (anything OSRSetFromUserInput takes: "EPSG:4326", a
/// PROJ string). Throws std::runtime_error naming `path`.
void writeHeightsGeoTiff(const std::string& path, int w, int h, const std::vector<float>& heights,
                         const std::array<double, 6>& geotransform, const std::string& crs,
                         const std::string& description, const std::string& source);

}  // namespace nph::datagen
