// A user DEM through GDAL (issue 14 item 2; scene/dem.h): real GeoTIFFs written through GDAL in
// the test (gdal_raster_writer.h), in a CRS other than the data's (UTM 17N over a Lambert grid),
// warped onto the model's mass points and the far square; the rule "the DEM wins where it has
// data"; the bad DEMs a user meets, each refused with the file and what was expected.
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "dem_writer.h"
#include "gdal_raster_writer.h"
#include "io/field_checks.h"
#include "scene/dem.h"
#include "scene/scene_file.h"
#include "scene/scene_setup.h"
#include "scene_test_support.h"
#include "volume/terrain_field.h"

namespace nph::scene {
namespace {

constexpr const char* kUtm17 = "EPSG:32617";
/// Inside the Lambert test grid (lambertVolumes: 300 × 240 km around −80°, 25°).
constexpr double kPeakLon_deg = -79.7, kPeakLat_deg = 25.2, kPeak_m = 2500.0, kSigma_m = 15000.0;
/// The second mountain lies 150 km west of the grid's west edge (world x = −150 km): only the far
/// field carries it.
constexpr double kFarPeakWorldX_m = -150000.0, kFarPeak_m = 2000.0;
constexpr double kNoData = -32768.0;

/// lon/lat -> UTM 17N easting/northing [m] through OSR (the test's own transform, not the warper's).
glm::dvec2 utmFromLonLat(double lon, double lat) {
  OGRSpatialReferenceH ll = OSRNewSpatialReference(nullptr), utm = OSRNewSpatialReference(nullptr);
  OSRSetFromUserInput(ll, "EPSG:4326");
  OSRSetFromUserInput(utm, kUtm17);
  OSRSetAxisMappingStrategy(ll, OAMS_TRADITIONAL_GIS_ORDER);
  OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformationH t = OCTNewCoordinateTransformation(ll, utm);
  double x = lon, y = lat;
  EXPECT_TRUE(OCTTransform(t, 1, &x, &y, nullptr));
  OCTDestroyCoordinateTransformation(t);
  OSRDestroySpatialReference(ll);
  OSRDestroySpatialReference(utm);
  return {x, y};
}

struct DemCase {
  ExtinctionVolumes volumes = test::lambertVolumes();  // 100 × 80 columns of 3 km
  volume::VolumeFrame frame = volume::frameOf(volumes, 4.0);
  SceneGeoreference geo{volumes, frame, {}, std::nullopt};
  glm::dvec2 peak_xy, far_peak_xy, hole_xy;
};

/// A 1 km UTM 17N Float32 DEM, 600 × 500 km around the grid: two Gaussian mountains (the near one
/// at kPeakLon/Lat, the far one west of the grid), nodata over a 20 km square inside the grid.
std::string writeUtmDem(const nph::test::ScratchDir& dir, DemCase& c) {
  c.peak_xy = c.geo.worldFromLonLat({kPeakLon_deg, kPeakLat_deg});
  // Off the far square's centre row and column, so that a flipped or shifted far field shows.
  c.far_peak_xy = {kFarPeakWorldX_m, 0.5 * c.frame.size_m().y + 80000.0};
  c.hole_xy = {0.75 * c.frame.size_m().x, 0.25 * c.frame.size_m().y};
  const LonLat farLl = c.geo.lonLatFromWorld(c.far_peak_xy), holeLl = c.geo.lonLatFromWorld(c.hole_xy);
  const glm::dvec2 peak = utmFromLonLat(kPeakLon_deg, kPeakLat_deg);
  const glm::dvec2 far = utmFromLonLat(farLl.lon_deg, farLl.lat_deg);
  const glm::dvec2 hole = utmFromLonLat(holeLl.lon_deg, holeLl.lat_deg);
  constexpr int kW = 600, kH = 500;
  constexpr double kPixel_m = 1000.0;
  const glm::dvec2 origin(peak.x - 400000.0, peak.y + 250000.0);  // north-west corner
  std::vector<double> h(std::size_t(kW) * kH);
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      const glm::dvec2 p(origin.x + (i + 0.5) * kPixel_m, origin.y - (j + 0.5) * kPixel_m);
      const auto gauss = [&](glm::dvec2 c0, double height) {
        const glm::dvec2 d = p - c0;
        return height * std::exp(-glm::dot(d, d) / (2.0 * kSigma_m * kSigma_m));
      };
      const bool inHole = std::abs(p.x - hole.x) < 10000.0 && std::abs(p.y - hole.y) < 10000.0;
      h[std::size_t(j) * kW + std::size_t(i)] = inHole ? kNoData : gauss(peak, kPeak_m) + gauss(far, kFarPeak_m);
    }
  }
  const std::string path = dir.file("utm.tif");
  test::writeGeoTiff(
      path, {kW, kH, 1, GDT_Float32, std::array<double, 6>{origin.x, kPixel_m, 0.0, origin.y, 0.0, -kPixel_m}, kUtm17},
      h, kNoData);
  return path;
}

/// Sub-cell position of the largest value of a w × h field (x fastest), by a parabola through the
/// maximum and its neighbours along each axis; in cells from (0, 0).
glm::dvec2 peakOf(const std::vector<float>& f, int w, int h) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < f.size(); ++k)
    if (!std::isnan(f[k]) && (std::isnan(f[best]) || f[k] > f[best])) best = k;
  const int i = int(best % std::size_t(w)), j = int(best / std::size_t(w));
  EXPECT_TRUE(i > 0 && j > 0 && i + 1 < w && j + 1 < h);
  const auto at = [&](int x, int y) { return double(f[std::size_t(y) * std::size_t(w) + std::size_t(x)]); };
  const auto vertex = [](double m, double z, double p) { return 0.5 * (m - p) / (m - 2.0 * z + p); };
  return {i + vertex(at(i - 1, j), at(i, j), at(i + 1, j)), j + vertex(at(i, j - 1), at(i, j), at(i, j + 1))};
}

TEST(Dem, UtmMountainLandsOnItsMassPointsAndBeyondTheGrid) {
  nph::test::ScratchDir dir("dem");
  DemCase c;
  const std::string path = writeUtmDem(dir, c);
  const DemRaster dem = DemRaster::open(path);
  EXPECT_TRUE(dem.hasNoData());
  const volume::DemHeights d = demHeightsFor(dem, c.geo, c.frame);
  ASSERT_EQ(d.model_m.size(), std::size_t(100 * 80));
  // Mass point (i, j) is world ((i + ½)·dx, (j + ½)·dy): the parabola's vertex in world metres.
  const glm::dvec2 cell(c.frame.voxel_size_m);
  const glm::dvec2 found = (peakOf(d.model_m, 100, 80) + glm::dvec2(0.5)) * cell;
  const double miss_m = glm::length(found - c.peak_xy);
  std::printf("[ dem] near summit at world (%.0f, %.0f) m, expected (%.0f, %.0f): %.0f m (a cell is 3000 m)\n", found.x,
              found.y, c.peak_xy.x, c.peak_xy.y, miss_m);
  // A parabola through three samples of a Gaussian σ = 5 cells is biased by < 0.02 cell.
  EXPECT_LT(miss_m, 0.1 * cell.x);
  // The far square: the far mountain at its place, to a tenth of a far pixel (~4.2 km).
  const glm::dvec2 farCell = (d.far_max_m - d.far_min_m) / glm::dvec2(d.far_size);
  // (Its own maximum: the far square holds the near mountain too, so the grid's half is masked.)
  std::vector<float> west = d.far_m;
  for (int j = 0; j < d.far_size.y; ++j)
    for (int i = 0; i < d.far_size.x; ++i)
      if (d.far_min_m.x + (i + 0.5) * farCell.x > -50000.0)
        west[std::size_t(j) * std::size_t(d.far_size.x) + std::size_t(i)] = NAN;
  const glm::dvec2 farFound = d.far_min_m + (peakOf(west, d.far_size.x, d.far_size.y) + glm::dvec2(0.5)) * farCell;
  std::printf("[ dem] far summit at world (%.0f, %.0f) m, expected (%.0f, %.0f): %.0f m (a far pixel is %.0f m)\n",
              farFound.x, farFound.y, c.far_peak_xy.x, c.far_peak_xy.y, glm::length(farFound - c.far_peak_xy),
              farCell.x);
  EXPECT_LT(glm::length(farFound - c.far_peak_xy), 0.25 * farCell.x);

  // The terrain: the DEM's heights inside the grid, the far mountain beyond it (× exaggeration 4),
  // sea level outside the DEM.
  const volume::TerrainField t = volume::terrainOf(c.volumes, c.frame, &d);
  ASSERT_TRUE(t.present());
  ASSERT_TRUE(t.hasFar());
  // Bilinear on 3 km cells under a σ = 15 km top: h·dx²/8·|h''|/h per axis ≈ 0.5 %, twice, plus
  // the 1 km DEM's own bilinear warp: within 2 %.
  EXPECT_NEAR(t.heightAt(c.peak_xy), 4.0 * kPeak_m, 4.0 * 0.02 * kPeak_m);
  // 4.2 km pixels, bilinear widened to the footprint: ≥ 95 % of the far Gaussian's top.
  EXPECT_GT(t.heightAt(c.far_peak_xy), 4.0 * 0.95 * kFarPeak_m);
  EXPECT_LE(t.heightAt(c.far_peak_xy), 4.0 * kFarPeak_m);
  EXPECT_EQ(t.heightAt({-1.2e6, -1.2e6}), 0.0);  // beyond the DEM: sea level
  // The march finds the far mountain: straight down onto its top.
  const glm::dvec3 above(c.far_peak_xy, 20000.0);
  EXPECT_NEAR(t.hitDistance(above, {0.0, 0.0, -1.0}, 0.0, 1e9), 20000.0 - t.heightAt(c.far_peak_xy), 1.0);
  // Without the DEM the lattice is sea level and nothing stands there.
  EXPECT_FALSE(volume::terrainOf(c.volumes, c.frame).present());
}

TEST(Dem, TheDemWinsWhereItHasDataTheModelFieldElsewhere) {
  nph::test::ScratchDir dir("dem");
  DemCase c;
  c.volumes.terrain_height_m.assign(std::size_t(100 * 80), 100.0f);  // the model's own field: 100 m
  const volume::DemHeights d = demHeightsFor(DemRaster::open(writeUtmDem(dir, c)), c.geo, c.frame);
  const volume::TerrainField t = volume::terrainOf(c.volumes, c.frame, &d);
  int fromDem = 0, fromModel = 0;
  for (std::size_t k = 0; k < d.model_m.size(); ++k) {
    if (std::isnan(d.model_m[k])) {
      EXPECT_EQ(t.height_m[k], 100.0f) << k;
      ++fromModel;
    } else {
      EXPECT_EQ(t.height_m[k], d.model_m[k]) << k;
      ++fromDem;
    }
  }
  // The 20 km nodata square is ~6 × 6 cells of 3 km (fewer: coverage under ½ at its edge counts as data).
  EXPECT_GE(fromModel, 16);
  EXPECT_LE(fromModel, 64);
  EXPECT_GT(fromDem, 7900);
  const glm::ivec2 hole(c.hole_xy / glm::dvec2(c.frame.voxel_size_m));
  EXPECT_TRUE(std::isnan(d.model_m[std::size_t(hole.y) * 100 + std::size_t(hole.x)]));
  // On the hole's lattice point the surface is the model's field exactly (the interpolating spline
  // passes through the lattice, glsl/common/terrain.glsl); between lattice points it rings by ~1 %
  // of the 100 m step at the hole's edge.
  const glm::dvec2 holePoint = (glm::dvec2(hole) + 0.5) * glm::dvec2(c.frame.voxel_size_m);
  EXPECT_NEAR(t.heightAt(holePoint), 4.0 * 100.0, 1e-3);
  EXPECT_NEAR(t.heightAt(c.hole_xy), 4.0 * 100.0, 4.0 * 1.5);
}

// A DEM finer than the model (docs/terrain.md "A DEM finer than the model"): the 1 km UTM DEM
// over 3 km cells refines the lattice 3 times; the field then holds the DEM at 1 km (its warp's
// values exactly), the model's own field bilinear between its mass points where the DEM has none.
TEST(Dem, AFinerDemRefinesTheLatticeAndKeepsTheModelFieldInItsHoles) {
  nph::test::ScratchDir dir("dem");
  DemCase c;
  // The model's own field: a tilted plane, which bilinear resampling reproduces exactly.
  c.volumes.terrain_height_m.resize(std::size_t(100 * 80));
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 100; ++i)
      c.volumes.terrain_height_m[std::size_t(j) * 100 + std::size_t(i)] = float(100 + 2 * i + j);
  const DemRaster dem = DemRaster::open(writeUtmDem(dir, c));
  const int r = demRefinementFor(dem, c.geo, c.frame);
  EXPECT_EQ(r, 3) << "1 km pixels in 3 km cells";
  const volume::DemHeights d = demHeightsFor(dem, c.geo, c.frame, true, r);
  ASSERT_EQ(d.model_m.size(), std::size_t(300 * 240));
  const volume::TerrainField t = volume::terrainOf(c.volumes, c.frame, &d);
  ASSERT_EQ(t.size, glm::ivec2(300, 240));
  EXPECT_NEAR(t.cell_m.x, c.frame.voxel_size_m.x / 3.0, 1e-9);
  int holes = 0;
  for (int j = 0; j < 240; ++j) {
    for (int i = 0; i < 300; ++i) {
      const std::size_t k = std::size_t(j) * 300 + std::size_t(i);
      if (!std::isnan(d.model_m[k])) {
        ASSERT_EQ(t.height_m[k], d.model_m[k]) << i << ", " << j;
        continue;
      }
      // The plane at the lattice point's continuous mass-point index ((i + ½)/3 − ½).
      const double qx = (i + 0.5) / 3.0 - 0.5, qy = (j + 0.5) / 3.0 - 0.5;
      EXPECT_NEAR(t.height_m[k], 100.0 + 2.0 * qx + qy, 1e-3) << i << ", " << j;
      ++holes;
    }
  }
  EXPECT_GT(holes, 3 * 3 * 16);  // the 20 km nodata square: ~20 × 20 points of 1 km
  // The summit of the σ = 15 km Gaussian: on 1 km points the bilinear top is within 0.1 %.
  EXPECT_NEAR(t.heightAt(c.peak_xy), 4.0 * kPeak_m, 4.0 * 0.003 * kPeak_m);
  // The march on the finer lattice: straight down onto the summit.
  const glm::dvec3 above(c.peak_xy, 20000.0);
  EXPECT_NEAR(t.hitDistance(above, {0.0, 0.0, -1.0}, 0.0, 1e9), 20000.0 - t.heightAt(c.peak_xy), 1.0);
  // A DEM as coarse as the model does not refine; the default is the mass points.
  EXPECT_EQ(demHeightsFor(dem, c.geo, c.frame, false).model_m.size(), std::size_t(100 * 80));
  EXPECT_THROW(demHeightsFor(dem, c.geo, c.frame, false, volume::kMaxTerrainRefine + 1), UsageError);
}

// The march on a refined lattice joined to the far field within two far pixels ("The join with
// the far field"), over rough ground (the generated Alpine DEM's relief placed over the Lambert
// test grid), rays grazing across the lattice, its edge, the fade and the far field, against a
// dense march (25 m steps, bisection): every ray that meets the ground gets a hit, never in front
// of the ground, and what it skips is what the march's floor step allows by design
// (glsl/common/terrain.glsl: near the surface a step is at least a quarter of the lattice's cell,
// half a far pixel beyond it, so a grazing ray may pass under a crest's tip that rises less than
// the bound's slope times one floor step). Measured: 5 of 400 rays skip a tip, by 22 m inside the
// footprint and up to 696 m (world, × 4) in the far field's 3.9 km pixels.
TEST(Dem, TheMarchFindsTheFirstGroundPointAcrossTheRefinedLatticeAndTheJoin) {
  nph::test::ScratchDir dir("dem");
  DemCase c;
  const datagen::DemSpec spec;  // the generator's function only: its seed
  const std::string path = dir.file("rough.tif");
  {
    // Heights of the Bernese Oberland (8° E, 46.5° N) moved onto the grid, through the same GeoTIFF
    // writer the generator uses (gdal_raster_writer.h).
    const int w = 800, h = 800;
    std::vector<double> z(std::size_t(w) * h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        z[std::size_t(j) * w + std::size_t(i)] =
            datagen::generatedDemHeight_m(spec, 8.0 - 4.0 + (i + 0.5) * 0.01, 46.5 + 4.0 - (j + 0.5) * 0.01);
    test::writeGeoTiff(path,
                       {w, h, 1, GDT_Float32, std::array<double, 6>{-84.0, 0.01, 0.0, 29.0, 0.0, -0.01}, "EPSG:4326"},
                       z, std::nullopt);
  }
  const DemRaster dem = DemRaster::open(path);
  const volume::DemHeights d = demHeightsFor(dem, c.geo, c.frame, true, demRefinementFor(dem, c.geo, c.frame));
  const volume::TerrainField t = volume::terrainOf(c.volumes, c.frame, &d);
  ASSERT_TRUE(t.hasFar());
  ASSERT_GT(t.max_m, 4.0 * 2000.0);
  const glm::dvec2 size(c.frame.size_m());
  int rays = 0, hits = 0;
  double worst_m = 0.0;
  for (int k = 0; k < 400; ++k) {
    // Eyes around the grid, low, rays across the edge and the fade at shallow angles.
    const double a = 2.0 * M_PI * k / 400.0;
    const glm::dvec3 o(0.5 * size.x + 0.8 * size.x * std::cos(a), 0.5 * size.y + 0.8 * size.y * std::sin(a),
                       t.max_m * (0.6 + 0.3 * ((k * 7) % 5) / 4.0));
    const glm::dvec2 to =
        glm::dvec2(0.5 * size.x, 0.5 * size.y) + 0.3 * size * glm::dvec2(std::sin(3.0 * a), std::cos(5.0 * a));
    const glm::dvec3 ray =
        glm::normalize(glm::dvec3(to - glm::dvec2(o), -(0.02 + 0.05 * (k % 4)) * glm::length(to - glm::dvec2(o))));
    const double tHit = t.hitDistance(o, ray, 0.0, 2.0e6);
    // The dense march: 25 m steps up to the conservative hit (or 1500 km), bisection on a crossing.
    double first = -1.0, prev = 0.0;
    const double end = tHit >= 0.0 ? tHit : 1.5e6;
    for (double s = 25.0; s <= end + 25.0; s += 25.0) {
      const glm::dvec3 p = o + s * ray;
      if (p.z <= t.heightAt(glm::dvec2(p))) {
        double lo = prev, hi = s;
        for (int b = 0; b < 30; ++b) {
          const double m = 0.5 * (lo + hi);
          const glm::dvec3 q = o + m * ray;
          (q.z > t.heightAt(glm::dvec2(q)) ? lo : hi) = m;
        }
        first = hi;
        break;
      }
      prev = s;
    }
    ++rays;
    if (first < 0.0) continue;  // the dense march found nothing before the conservative hit
    ++hits;
    ASSERT_GE(tHit, 0.0) << "ray " << k << ": the march missed ground at " << first << " m";
    // How deep the skipped ground reaches above the ray (world metres, exaggerated).
    double depth_m = 0.0;
    for (double s = first; s < tHit; s += 5.0) {
      const glm::dvec3 p = o + s * ray;
      depth_m = std::max(depth_m, t.heightAt(glm::dvec2(p)) - p.z);
    }
    if (tHit - first > 1.0)
      std::printf("[ dem] ray %d: hit %.0f m beyond the first crossing at (%.0f, %.0f) km of the %.0f x %.0f km "
                  "footprint, skipped ground %.2f m above the ray\n",
                  k, tHit - first, (o + first * ray).x / 1e3, (o + first * ray).y / 1e3, size.x / 1e3, size.y / 1e3,
                  depth_m);
    EXPECT_GE(tHit, first - 0.5) << "ray " << k << ": a hit in front of the ground";
    const glm::dvec3 at = o + first * ray;
    const bool inLattice = at.x > -t.fade_m && at.y > -t.fade_m && at.x < size.x + t.fade_m && at.y < size.y + t.fade_m;
    const double floor_m =
        inLattice ? 0.25 * std::min(t.cell_m.x, t.cell_m.y) : 0.5 * std::min(t.far_cell_m.x, t.far_cell_m.y);
    EXPECT_LE(depth_m, t.lipschitz * floor_m) << "ray " << k << ": more than one floor step's rise skipped";
    worst_m = std::max(worst_m, depth_m);
  }
  std::printf("[ dem] %d of %d rough rays meet ground; skipped crest tips rise at most %.2f m above the ray (slope "
              "bound %.2f)\n",
              hits, rays, worst_m, t.lipschitz);
  EXPECT_GT(hits, 300);
}

// nephele-gen dem (data_tools/dem_writer.h): a Float32 GeoTIFF that the user-DEM path opens as it
// would SRTM (CRS, metres, one band), whose pixels are the generator's function at their centres,
// and whose relief reads as mountains: a range along the Alps' axis with steep slopes and deep
// valleys, a low foreland, sea level far away.
TEST(Dem, GeneratedAlpineDemIsARealGeoTiffOfMountains) {
  nph::test::ScratchDir dir("dem");
  datagen::DemSpec spec;
  spec.lon_min_deg = 6.0, spec.lat_min_deg = 45.0, spec.lon_max_deg = 10.0, spec.lat_max_deg = 48.0;
  spec.pixel_deg = 0.01;
  const std::string path = dir.file("alps.tif");
  const datagen::DemTruth truth = datagen::writeGeneratedDem(spec, path);
  ASSERT_EQ(truth.width, 400);
  ASSERT_EQ(truth.height, 300);
  const DemRaster dem = DemRaster::open(path);  // the user-DEM path's checks: CRS, metres, a band
  EXPECT_EQ(dem.width(), 400);
  EXPECT_FALSE(dem.hasNoData());
  // Read back through GDAL: the generator's function at the pixel centres, bit for bit.
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  std::vector<float> h(std::size_t(400) * 300);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, 400, 300, h.data(), 400, 300, GDT_Float32, 0, 0),
            CE_None);
  GDALClose(ds);
  for (int j = 0; j < 300; j += 37)
    for (int i = 0; i < 400; i += 41)
      EXPECT_EQ(h[std::size_t(j) * 400 + std::size_t(i)],
                float(datagen::generatedDemHeight_m(spec, 6.0 + (i + 0.5) * 0.01, 48.0 - (j + 0.5) * 0.01)));
  // Mountains: the Bernese Oberland's axis (7.5–9° E, 46.4–46.7° N) reaches 2500 m and more,
  // with a tenth or more of its slopes steeper than 30° (pixels ≈ 0.77 × 1.11 km); the Swiss
  // plateau 100 km north (47.4–47.6° N) stays under 1200 m.
  const double dx_m = 0.01 * 111320.0 * std::cos(46.5 * M_PI / 180.0), dy_m = 0.01 * 111320.0;
  double axisMax = 0.0, plateauMax = 0.0;
  int axisPixels = 0, steep = 0;
  for (int j = 1; j + 1 < 300; ++j) {
    const double lat = 48.0 - (j + 0.5) * 0.01;
    for (int i = 1; i + 1 < 400; ++i) {
      const double lon = 6.0 + (i + 0.5) * 0.01;
      const auto at = [&](int x, int y) { return double(h[std::size_t(y) * 400 + std::size_t(x)]); };
      if (lon > 7.5 && lon < 9.0 && lat > 46.4 && lat < 46.7) {
        axisMax = std::max(axisMax, at(i, j));
        const double gx = (at(i + 1, j) - at(i - 1, j)) / (2.0 * dx_m),
                     gy = (at(i, j + 1) - at(i, j - 1)) / (2.0 * dy_m);
        steep += std::hypot(gx, gy) > std::tan(30.0 * M_PI / 180.0) ? 1 : 0;
        ++axisPixels;
      }
      if (lon > 7.5 && lon < 9.0 && lat > 47.4 && lat < 47.6) plateauMax = std::max(plateauMax, at(i, j));
    }
  }
  std::printf(
      "[ dem] generated: axis max %.0f m, %.1f %% of its slopes > 30°, plateau max %.0f m, range %.0f..%.0f m\n",
      axisMax, 100.0 * steep / axisPixels, plateauMax, truth.min_m, truth.max_m);
  EXPECT_GT(axisMax, 2500.0);
  EXPECT_LT(truth.max_m, io::kHighestTerrain_m);
  EXPECT_GE(truth.min_m, 0.0);
  EXPECT_GT(double(steep) / axisPixels, 0.1);
  EXPECT_LT(plateauMax, 1200.0);
  // Far from the range: sea level (the generator's function 550 km south of the axis).
  EXPECT_LT(datagen::generatedDemHeight_m(spec, 8.0, 39.0), 1.0);
  // Deterministic: the same seed gives the same heights, another seed other ridges.
  datagen::DemSpec other = spec;
  other.seed = 2;
  EXPECT_NE(datagen::generatedDemHeight_m(other, 8.0, 46.5), datagen::generatedDemHeight_m(spec, 8.0, 46.5));
}

void expectDemError(const std::string& path, const std::string& expected) {
  DemCase c;
  try {
    (void)demHeightsFor(DemRaster::open(path), c.geo, c.frame);
    ADD_FAILURE() << path << ": no error, expected one saying \"" << expected << "\"";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(expected), std::string::npos) << what;
  }
}

TEST(Dem, BadDemsAreRefusedNamingTheFileAndWhatWasExpected) {
  nph::test::ScratchDir dir("dem");
  const std::array<double, 6> lonLatGt{-82.0, 0.01, 0.0, 27.0, 0.0, -0.01};  // over the grid
  expectDemError(dir.file("missing.tif"), "DEM not found");
  std::ofstream(dir.file("notes.tif")) << "heights: see the attached spreadsheet\n";
  expectDemError(dir.file("notes.tif"), "not a raster GDAL reads");
  // Georeferenced in metres of no CRS.
  test::writeGeoTiff(dir.file("nocrs.tif"),
                     {40, 30, 1, GDT_Float32, std::array<double, 6>{500000.0, 100.0, 0.0, 4e6, 0.0, -100.0}, ""},
                     std::vector<double>(40 * 30, 100.0));
  expectDemError(dir.file("nocrs.tif"), "has no coordinate reference system");
  // Truncated: a valid DEM cut after its header and a third of its pixels.
  const std::string cut = dir.file("truncated.tif");
  test::writeGeoTiff(cut, {400, 300, 1, GDT_Float32, lonLatGt, "EPSG:4326"}, std::vector<double>(400 * 300, 50.0));
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) / 3);
  expectDemError(cut, "cannot read the DEM");
  // Heights in centimetres: 2500 m read as 250000.
  test::writeGeoTiff(dir.file("centimetres.tif"), {400, 300, 1, GDT_Float32, lonLatGt, "EPSG:4326"},
                     std::vector<double>(400 * 300, 250000.0));
  expectDemError(dir.file("centimetres.tif"), "expected metres above sea level in [-1000, 9000]");
  // A picture, not heights: 8-bit, or three bands.
  test::writeGeoTiff(dir.file("byte.tif"), {40, 30, 1, GDT_Byte, lonLatGt, "EPSG:4326"},
                     std::vector<double>(40 * 30, 10.0));
  expectDemError(dir.file("byte.tif"), "expected heights [m] as Int16");
  test::writeGeoTiff(dir.file("rgb.tif"), {40, 30, 3, GDT_Int16, lonLatGt, "EPSG:4326"},
                     std::vector<double>(40 * 30 * 3, 10.0));
  expectDemError(dir.file("rgb.tif"), "DEM has 3 bands, expected one band of heights [m]");
}

TEST(Dem, SceneFileKeyAndPreparedScene) {
  nph::test::ScratchDir dir("dem");
  const SceneDescription s = parseSceneText(R"({"terrain": {"dem": "srtm/n25w080.tif"}})", "s.json", "/base");
  ASSERT_TRUE(s.terrain);
  EXPECT_EQ(s.terrain->dem, "/base/srtm/n25w080.tif");
  EXPECT_FALSE(parseSceneText("{}", "s.json").terrain);
  EXPECT_THROW(parseSceneText(R"({"terrain": {"dme": "x.tif"}})", "s.json"), InputError);
  EXPECT_THROW(parseSceneText(R"({"terrain": {}})", "s.json"), InputError);
  // prepareScene warps it for the session (the model lattice and the far square).
  DemCase c;
  const std::string path = writeUtmDem(dir, c);
  SceneDescription scene = parseSceneText("{\"terrain\": {\"dem\": \"" + path + "\"}}", "s.json");
  const PreparedScene p = prepareScene(scene, c.volumes);
  ASSERT_TRUE(p.dem);
  // On the lattice refined to the DEM's 1 km pixels (3 km cells: demRefinementFor).
  EXPECT_EQ(p.dem->refine, 3);
  EXPECT_EQ(p.dem->model_m.size(), std::size_t(300 * 240));
  EXPECT_EQ(p.dem->far_size, glm::ivec2(kFarBasemapPixels));
  const WorldRect far = farBasemapRectangle(p.frame);
  EXPECT_EQ(p.dem->far_min_m, far.min_m);
  EXPECT_EQ(p.dem->far_max_m, far.max_m);
  // The globe's terrain ends with its table: no far field is warped for it.
  scene = parseSceneText("{\"view\": \"globe\", \"terrain\": {\"dem\": \"" + path + "\"}}", "s.json");
  const PreparedScene globe = prepareScene(scene, c.volumes);
  ASSERT_TRUE(globe.dem);
  ASSERT_EQ(globe.dem->model_m.size(), p.dem->model_m.size());
  for (std::size_t k = 0; k < p.dem->model_m.size(); ++k) {  // the same heights, NaN (no data) included
    const float a = globe.dem->model_m[k], b = p.dem->model_m[k];
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << k;
  }
  EXPECT_TRUE(globe.dem->far_m.empty());
}

}  // namespace
}  // namespace nph::scene
