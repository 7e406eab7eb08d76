// A generated Alpine DEM as a GeoTIFF through GDAL (dem_writer.h).
#include "dem_writer.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace nph::datagen {
namespace {

constexpr double kKmPerDeg = 111.32;  // one degree of latitude (and of longitude × cos φ) [km]

/// The belt's axis (lon, lat): the real Alps' arc, from the Maritime Alps north to Mont Blanc,
/// east along the Bernese Oberland and the Hohe Tauern, to the Vienna basin.
constexpr std::array<std::array<double, 2>, 6> kAxis = {
    {{6.8, 44.1}, {6.9, 45.8}, {8.0, 46.5}, {10.5, 46.6}, {13.0, 47.1}, {16.0, 47.7}}};
constexpr double kAxisLat_deg = 46.5;       // the x scale's latitude (cos φ) for the belt's distances
constexpr double kBeltHalfWidth_km = 75.0;  // the range's envelope: exp(−(d/w)²)
constexpr double kForeland_m = 450.0, kForelandWidth_km = 160.0;  // the plains falling to the sea
constexpr double kBaseWavelength_km = 24.0;  // the first octave: main ridges 10–25 km apart, as the Alps' valleys
constexpr int kOctaves = 8;                  // down to 24/2⁷ ≈ 0.19 km, below the pixel
constexpr double kRidgeCap = 1.3;            // the ridged sum's share of peak_m is min(sum, cap)/cap
constexpr double kWarp_km = 18.0;            // domain warp: ridges that bend

/// A 64-bit mix (splitmix64's finaliser): the lattice's random numbers, seed-deterministic.
std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Perlin's gradient noise (2002's quintic fade) on the integer lattice, in [−1, 1] roughly.
double gradientNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const double u = x - fx, v = y - fy;
  const auto grad = [&](int i, int j, double dx, double dy) {
    const std::uint64_t h =
        mix64(seed ^ mix64(std::uint64_t(std::uint32_t(i)) | (std::uint64_t(std::uint32_t(j)) << 32)));
    const double a = double(h >> 11) * (2.0 * M_PI / 9007199254740992.0);
    return std::cos(a) * dx + std::sin(a) * dy;
  };
  const int i = int(fx), j = int(fy);
  const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
  const double su = fade(u), sv = fade(v);
  const double n00 = grad(i, j, u, v), n10 = grad(i + 1, j, u - 1.0, v);
  const double n01 = grad(i, j + 1, u, v - 1.0), n11 = grad(i + 1, j + 1, u - 1.0, v - 1.0);
  return 1.4142 * ((n00 * (1.0 - su) + n10 * su) * (1.0 - sv) + (n01 * (1.0 - su) + n11 * su) * sv);
}

/// Musgrave's ridged multifractal (Ebert et al. 2003 §16.4, "RidgedMultifractal" with H = 1,
/// lacunarity 2, offset 1, gain 2): each octave's signal (1 − |n|)² is sharp on the noise's zero
/// lines (the ridges) and weighted by the previous octave's, so the fine detail lies on the ridges
/// and the valleys between them stay smooth — the look of eroded mountains without an erosion
/// simulation. Result in about [0, 1].
double ridgedMultifractal(double x, double y, std::uint64_t seed) {
  double sum = 0.0, weight = 1.0, amplitude = 1.0, norm = 0.0;
  for (int o = 0; o < kOctaves; ++o) {
    double signal = 1.0 - std::abs(gradientNoise(x, y, seed + std::uint64_t(o) * 0x1000193ULL));
    signal *= signal;
    signal *= weight;
    weight = std::clamp(signal * 2.0, 0.0, 1.0);
    sum += signal * amplitude;
    norm += amplitude;
    amplitude *= 0.5;
    x *= 2.0;
    y *= 2.0;
  }
  return sum / norm * 1.6;
}

/// fBm of the gradient noise: the foreland's gentle hills and the domain warp.
double fbm(double x, double y, std::uint64_t seed, int octaves) {
  double sum = 0.0, amplitude = 0.5;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * gradientNoise(x, y, seed + 7919ULL * std::uint64_t(o + 1));
    amplitude *= 0.5;
    x *= 2.0;
    y *= 2.0;
  }
  return sum;
}

/// Distance [km] from (x, y) [km] to the belt's axis.
double axisDistance_km(double x, double y) {
  const double kx = kKmPerDeg * std::cos(kAxisLat_deg * M_PI / 180.0);
  double best = 1e30;
  for (std::size_t k = 0; k + 1 < kAxis.size(); ++k) {
    const double ax = kAxis[k][0] * kx, ay = kAxis[k][1] * kKmPerDeg;
    const double bx = kAxis[k + 1][0] * kx, by = kAxis[k + 1][1] * kKmPerDeg;
    const double ex = bx - ax, ey = by - ay;
    const double t = std::clamp(((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    best = std::min(best, std::hypot(x - ax - t * ex, y - ay - t * ey));
  }
  return best;
}

}  // namespace

double generatedDemHeight_m(const DemSpec& spec, double lon_deg, double lat_deg) {
  // Plane coordinates [km] at the belt's latitude scale (the range spans ±5° of latitude: the
  // noise's wavelengths stretch by at most 10 % across it, which is of no account for synthesis).
  const double x = lon_deg * kKmPerDeg * std::cos(kAxisLat_deg * M_PI / 180.0), y = lat_deg * kKmPerDeg;
  const std::uint64_t seed = mix64(spec.seed);
  // Domain warp (Quilez's "warping"): the ridges bend instead of following the lattice's axes.
  const double wx = x + kWarp_km * fbm(x / 120.0, y / 120.0, seed ^ 0xa5a5ULL, 4);
  const double wy = y + kWarp_km * fbm(x / 120.0 + 5.2, y / 120.0 + 1.3, seed ^ 0x5a5aULL, 4);
  const double d = axisDistance_km(wx, wy);
  const double belt = std::exp(-(d / kBeltHalfWidth_km) * (d / kBeltHalfWidth_km));
  const double ridges = ridgedMultifractal(wx / kBaseWavelength_km, wy / kBaseWavelength_km, seed);
  // The foreland (Swiss plateau, Po plain, Bavarian uplands): a few hundred metres of gentle
  // hills, falling to sea level away from the range.
  const double fl = std::exp(-(d / kForelandWidth_km) * (d / kForelandWidth_km));
  const double foreland_m = kForeland_m * fl * (0.75 + 0.5 * fbm(x / 40.0, y / 40.0, seed ^ 0x77ULL, 5));
  // The range: the ridges' height grows with the belt, and the valleys between them still fall
  // towards the foreland (the belt times the ridges' share), so the range has deep valleys. The
  // ridged sum rarely exceeds kRidgeCap; above it the crest is held (a summit plateau is rarer
  // than a 7 km spike).
  const double share = std::clamp(ridges, 0.0, kRidgeCap) / kRidgeCap;
  const double range_m = spec.peak_m * belt * std::pow(share, 1.5);
  return std::max(0.0, foreland_m + range_m);
}

DemTruth writeGeneratedDem(const DemSpec& spec, const std::string& path) {
  const int w = int(std::lround((spec.lon_max_deg - spec.lon_min_deg) / spec.pixel_deg));
  const int h = int(std::lround((spec.lat_max_deg - spec.lat_min_deg) / spec.pixel_deg));
  if (w < 2 || h < 2 || !(spec.pixel_deg > 0.0)) {
    throw std::runtime_error(
        fmt::format("{}: DEM of {}x{} pixels; expected a rectangle of at least 2x2 pixels", path, w, h));
  }
  std::vector<float> heights(std::size_t(w) * std::size_t(h));
  DemTruth truth{w, h, 1e30, -1e30};
  for (int j = 0; j < h; ++j) {  // row 0 north, as GeoTIFF's geotransform below
    const double lat = spec.lat_max_deg - (j + 0.5) * spec.pixel_deg;
    for (int i = 0; i < w; ++i) {
      const double z = generatedDemHeight_m(spec, spec.lon_min_deg + (i + 0.5) * spec.pixel_deg, lat);
      heights[std::size_t(j) * std::size_t(w) + std::size_t(i)] = float(z);
      truth.min_m = std::min(truth.min_m, z);
      truth.max_m = std::max(truth.max_m, z);
    }
  }
  const std::array<double, 6> gt = {spec.lon_min_deg, spec.pixel_deg, 0.0, spec.lat_max_deg, 0.0, -spec.pixel_deg};
  writeHeightsGeoTiff(path, w, h, heights, gt, "EPSG:4326",
                      "height above sea level (generated: nephele-gen dem, docs/terrain.md)",
                      fmt::format("nephele-gen dem --seed {} (synthesis, not a survey)", spec.seed));
  return truth;
}

void writeHeightsGeoTiff(const std::string& path, int w, int h, const std::vector<float>& heights,
                         const std::array<double, 6>& geotransform, const std::string& crs,
                         const std::string& description, const std::string& source) {
  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (!driver) throw std::runtime_error(fmt::format("{}: GDAL has no GTiff driver", path));
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  if (OSRSetFromUserInput(srs, crs.c_str()) != OGRERR_NONE) {
    OSRDestroySpatialReference(srs);
    throw std::runtime_error(fmt::format("{}: GDAL does not understand the CRS '{}'", path, crs));
  }
  const char* options[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", "TILED=YES", nullptr};
  GDALDatasetH ds = GDALCreate(driver, path.c_str(), w, h, 1, GDT_Float32, const_cast<char**>(options));
  if (!ds) {
    OSRDestroySpatialReference(srs);
    throw std::runtime_error(fmt::format("{}: GDAL cannot create the GeoTIFF: {}", path, CPLGetLastErrorMsg()));
  }
  double gt[6];
  std::copy(geotransform.begin(), geotransform.end(), gt);
  GDALSetGeoTransform(ds, gt);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  GDALSetProjection(ds, wkt);
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  GDALSetRasterUnitType(band, "m");
  GDALSetDescription(band, description.c_str());
  GDALSetMetadataItem(ds, "SOURCE", source.c_str(), nullptr);
  const CPLErr err =
      GDALRasterIO(band, GF_Write, 0, 0, w, h, const_cast<float*>(heights.data()), w, h, GDT_Float32, 0, 0);
  GDALClose(ds);
  if (err != CE_None)
    throw std::runtime_error(fmt::format("{}: GDAL cannot write the heights: {}", path, CPLGetLastErrorMsg()));
}

}  // namespace nph::datagen
