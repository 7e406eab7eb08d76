// Placement (issue 5, "a generated storm centred at a known lon/lat appears at that pixel on the
// basemap", for Lambert and Mercator): generator (data_tools) -> wrfout -> loader (io/) -> optics
// (physics/) -> SceneGeoreference -> reprojected basemap. The truth is the generator's own
// XLAT/XLONG (computed with its own PROJ set-up, lat_0 = TRUELAT1, not the loader's) and the
// storm centre it placed; the basemap is a synthetic image whose colour encodes lon/lat.
#include <gtest/gtest.h>

#include <cmath>

#include "gdal_raster_writer.h"
#include "io/model_file.h"
#include "physics/optics_settings.h"
#include "physics/volume_builder.h"
#include "scene/basemap.h"
#include "scene/georeference.h"
#include "scene_test_support.h"
#include "wrf_hurricane.h"

namespace nph::scene {
namespace {

const char* nameOf(datagen::WrfProjection p) {
  switch (p) {
    case datagen::WrfProjection::Lambert: return "Lambert";
    case datagen::WrfProjection::Mercator: return "Mercator";
    case datagen::WrfProjection::RotatedLatLon: return "RotatedLatLon";
    default: return "Other";
  }
}

/// The generated storm of these tests (80×72×20 columns, 5 km, one time) written as a wrfout in
/// `projection`, loaded and turned into volumes, and its frame at height × 10.
struct GeneratedStorm {
  datagen::WrfHurricaneSpec spec;
  datagen::WrfTruth truth;
  ExtinctionVolumes v;
  volume::VolumeFrame frame;
  GeneratedStorm(const std::string& path, datagen::WrfProjection projection) {
    spec.nx = 80;
    spec.ny = 72;
    spec.nz = 20;
    spec.ntimes = 1;
    spec.dx_m = 5000.0;
    spec.projection = projection;
    truth = datagen::writeWrfHurricane(spec, path);
    v = physics::buildExtinctionVolumes(io::openModelFile(path).load(0), physics::defaultOptics(),
                                        physics::VerticalGridOptions{});
    frame = volume::frameOf(v, 10.0);
  }
};

class Placement : public ::testing::TestWithParam<datagen::WrfProjection> {};

TEST_P(Placement, StormAppearsAtItsLonLatOnTheBasemap) {
  nph::test::ScratchDir dir("scene");
  const GeneratedStorm storm(dir.file("wrfout.nc"), GetParam());
  // Named references, not a structured binding: clang 14 (the sanitizer build) cannot capture
  // structured bindings in a lambda (C++20, P1091).
  const auto& spec = storm.spec;
  const auto& truth = storm.truth;
  const auto& v = storm.v;
  const auto& frame = storm.frame;
  const SceneGeoreference geo(v, frame);

  // 1. Every 7th mass point: world voxel centre -> lon/lat agrees with the generator's XLAT/XLONG
  //    (stored as float in the file; the truth is double).
  double maxErr = 0.0;
  for (int j = 0; j < v.ny; j += 7) {
    for (int i = 0; i < v.nx; i += 7) {
      const glm::dvec3 w = frame.worldFromGrid({i + 0.5, j + 0.5, 0.5});
      const LonLat ll = geo.lonLatFromWorld({w.x, w.y});
      const std::size_t p = std::size_t(j) * std::size_t(v.nx) + std::size_t(i);
      maxErr = std::max({maxErr, std::abs(ll.lon_deg - truth.lon_deg[p]), std::abs(ll.lat_deg - truth.lat_deg[p])});
    }
  }
  EXPECT_LT(maxErr, 1e-6) << nameOf(GetParam());

  // 2. The storm centre (generator: metres from mass point 0) in world metres and lon/lat.
  const glm::dvec2 stormWorld{truth.storm_centre_x_m + 0.5 * frame.voxel_size_m.x,
                              truth.storm_centre_y_m + 0.5 * frame.voxel_size_m.y};
  const auto [stormLon, stormLat] = datagen::stormCentreLonLat(truth, spec.dx_m);
  const LonLat stormLl{stormLon, stormLat};
  const LonLat fromWorld = geo.lonLatFromWorld(stormWorld);
  // Bilinear interpolation of lon/lat between mass points 5 km apart errs by < 1e-4° here.
  EXPECT_NEAR(fromWorld.lon_deg, stormLl.lon_deg, 1e-4);
  EXPECT_NEAR(fromWorld.lat_deg, stormLl.lat_deg, 1e-4);

  // 3. The storm really is there in the volume: the eye (clear within 14 km) has a much thinner
  //    water column than the eyewall ring at 40 km.
  auto column = [&](glm::dvec2 w) {
    const glm::dvec3 g = frame.gridFromWorld({w.x, w.y, frame.z_bottom_m});
    const int i = static_cast<int>(g.x), j = static_cast<int>(g.y);
    double tau = 0.0;
    for (int k = 0; k < v.nz; ++k) tau += double(v.water_per_m[v.index(i, j, k)]) * v.dz_m;
    return tau;
  };
  double ring = 0.0;
  constexpr int kRingSamples = 8;
  for (int a = 0; a < kRingSamples; ++a) {
    const double t = 2.0 * 3.14159265358979 * a / kRingSamples;
    ring += column(stormWorld + 40000.0 * glm::dvec2(std::cos(t), std::sin(t))) / kRingSamples;
  }
  EXPECT_GT(ring, 10.0);
  EXPECT_LT(column(stormWorld), 0.3 * ring) << "eye " << column(stormWorld) << " ring " << ring;

  // 4. On the reprojected basemap, the pixel containing the storm centre shows the storm's
  //    lon/lat (within that pixel's extent).
  LinearRgbImage coded{720, 360, std::vector<float>(720 * 360 * 3)};
  for (int y = 0; y < 360; ++y) {
    for (int x = 0; x < 720; ++x) {
      const std::size_t o = (std::size_t(y) * 720 + std::size_t(x)) * 3;
      coded.rgb[o] = static_cast<float>((x + 0.5) / 720.0);
      coded.rgb[o + 1] = static_cast<float>(1.0 - (y + 0.5) / 360.0);
    }
  }
  const EquirectangularImage source(std::move(coded));
  const WorldRect rect = basemapRectangle(frame, 0.5);
  const int W = 400, H = 360;
  const LinearRgbImage map = reprojectBasemap(source, geo, rect, W, H);
  const int px = static_cast<int>((stormWorld.x - rect.min_m.x) / (rect.max_m.x - rect.min_m.x) * W);
  const int py = static_cast<int>((rect.max_m.y - stormWorld.y) / (rect.max_m.y - rect.min_m.y) * H);
  const glm::vec3 c = map.at(px, py);
  const double pixelDeg = (rect.max_m.x - rect.min_m.x) / W / 111000.0;  // pixel size in degrees, roughly
  EXPECT_NEAR(double(c.r) * 360.0 - 180.0, stormLl.lon_deg,
              pixelDeg / std::cos(stormLl.lat_deg * 3.14159265358979 / 180.0));
  EXPECT_NEAR(double(c.g) * 180.0 - 90.0, stormLl.lat_deg, pixelDeg);
}

// Issue 14 item 3: a GeoTIFF in another CRS than the data's — Web Mercator (EPSG:3857) imagery under
// a Lambert conformal WRF grid — lands at the right place after GDAL's warp. The GeoTIFF (written
// with GDAL, 1 km pixels around the storm) stores each pixel centre's lon/lat as its colour,
// computed with the spherical Mercator's closed-form inverse (Snyder 1987 eq. 7-4, 7-5 on
// R = 6378137 m, the EPSG:3857 definition), not with PROJ; the warped pixel that contains the
// storm centre must show the storm's lon/lat (the generator's truth) within that pixel.
TEST(PlacementGdal, WebMercatorGeoTiffUnderALambertGridShowsTheStormAtItsLonLat) {
  nph::test::ScratchDir dir("scene");
  const GeneratedStorm storm(dir.file("wrfout.nc"), datagen::WrfProjection::Lambert);
  const auto& [spec, truth, v, frame] = storm;
  const SceneGeoreference geo(v, frame);
  const auto [stormLon, stormLat] = datagen::stormCentreLonLat(truth, spec.dx_m);

  // 1. The GeoTIFF: 1 km Web Mercator pixels over ±400 km around the storm (covering the footprint).
  constexpr double kR = 6378137.0, kDegPerRad = 180.0 / 3.14159265358979323846;
  const double cx = stormLon / kDegPerRad * kR;
  const double cy = kR * std::log(std::tan(3.14159265358979323846 / 4.0 + stormLat / kDegPerRad / 2.0));
  const int n = 800;
  const double pixel_m = 1000.0, x0 = cx - 0.5 * n * pixel_m, y0 = cy + 0.5 * n * pixel_m;
  std::vector<double> px(std::size_t(n) * std::size_t(n) * 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = x0 + (i + 0.5) * pixel_m, y = y0 - (j + 0.5) * pixel_m;
      const std::size_t o = (std::size_t(j) * std::size_t(n) + std::size_t(i)) * 3;
      px[o] = x / kR * kDegPerRad;                                                                  // lon
      px[o + 1] = (2.0 * std::atan(std::exp(y / kR)) - 0.5 * 3.14159265358979323846) * kDegPerRad;  // lat
      px[o + 2] = 0.5;
    }
  }
  const std::string tif = dir.file("mercator.tif");
  test::writeGeoTiff(
      tif, {n, n, 3, GDT_Float32, std::array<double, 6>{x0, pixel_m, 0.0, y0, 0.0, -pixel_m}, "EPSG:3857"}, px);
  const BasemapRaster raster = BasemapRaster::open(tif);
  EXPECT_FALSE(raster.wholeEarth());

  // 2. Warped under the data's frame: the storm's pixel shows the storm's lon/lat.
  const WorldRect rect = basemapRectangle(frame, 0.1);
  const int W = 420, H = 380;
  const LinearRgbImage map = reprojectBasemap(raster, geo, rect, W, H);
  const glm::dvec2 stormWorld{truth.storm_centre_x_m + 0.5 * frame.voxel_size_m.x,
                              truth.storm_centre_y_m + 0.5 * frame.voxel_size_m.y};
  const double fx = (stormWorld.x - rect.min_m.x) / (rect.max_m.x - rect.min_m.x) * W;
  const double fy = (rect.max_m.y - stormWorld.y) / (rect.max_m.y - rect.min_m.y) * H;
  const glm::vec3 c = map.at(static_cast<int>(fx), static_cast<int>(fy));
  // Half an output pixel (~1 km) in degrees, plus float storage of the colour (1e-5°).
  const double halfPixelDeg = 0.5 * (rect.max_m.x - rect.min_m.x) / W / 111000.0;
  EXPECT_NEAR(double(c.r), stormLon, halfPixelDeg / std::cos(stormLat / kDegPerRad) + 1e-5);
  EXPECT_NEAR(double(c.g), stormLat, halfPixelDeg + 1e-5);
  EXPECT_FLOAT_EQ(c.b, 0.5f);

  // 3. Every output pixel the raster covers shows its own lon/lat (the data's PROJ inverse): the
  //    whole warp, not one point, within the bilinear error of the Mercator's curved latitude
  //    over a 1 km pixel (< 1e-6°), the approximating transformer (5e-4 source pixels ≈ 5e-6°) and
  //    float storage of the colour (~1e-5° at lon −80).
  double maxErr = 0.0;
  for (int y = 0; y < H; y += 7) {
    for (int x = 0; x < W; x += 7) {
      const LonLat ll = geo.lonLatFromWorld(worldFromBasemapPixel(rect, W, H, x, y));
      const glm::vec3 m = map.at(x, y);
      ASSERT_FLOAT_EQ(m.b, 0.5f) << "pixel " << x << "," << y << " not covered";
      maxErr = std::max({maxErr, std::abs(double(m.r) - ll.lon_deg), std::abs(double(m.g) - ll.lat_deg)});
    }
  }
  EXPECT_LT(maxErr, 5e-5);
}

INSTANTIATE_TEST_SUITE_P(Wrf, Placement,
                         ::testing::Values(datagen::WrfProjection::Lambert, datagen::WrfProjection::Mercator,
                                           datagen::WrfProjection::RotatedLatLon),
                         [](const auto& param_info) { return std::string(nameOf(param_info.param)); });

}  // namespace
}  // namespace nph::scene
