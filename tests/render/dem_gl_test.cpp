// A user DEM through the renderer (issue 14 item 2: "... and, optionally, a user DEM (GeoTIFF
// through GDAL)"; scene/dem.h). The model is issue 13's coarse storm over a flat sea (72 × 64
// columns at 10 km, Lambert, HGT = 0); the DEM is a lon/lat (EPSG:4326) Float32 GeoTIFF written
// through GDAL here, with two 3000 m Gaussian mountains (σ = 35 km): one inside the model's grid
// at 76.2° W, 24.3° N, one 250 km beyond its west edge, where only the DEM's far field (the far
// basemap's square) carries it. The chain under test: scene "terrain": {"dem"} → DemRaster →
// GDAL's warper onto the mass points and the far square → terrainOf ("the DEM wins") →
// VolumeTextures (UNIT_TERRAIN, UNIT_FAR_TERRAIN) → the eye pass's march (glsl/common/terrain.glsl)
// → the frame.
//
// Each summit is placed by terrain_gl_test.cpp's method: over a lon/lat-coded basemap (constant
// blue per 10° square, so blue/blue_true is the shading), the ground point showing the summit's
// lon/lat must lie within 1.5 px of the projection of its world point (x, y, e·h(x, y)), h the CPU
// twin of the same field. With the knob terrain off the same lon/lat shows tens of pixels away.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../scene/gdal_raster_writer.h"
#include "render_scenes.h"
#include "support/gl_fixture.h"
#include "volume/terrain_field.h"

namespace nph::test {
namespace {

constexpr double kNearLon_deg = -76.2, kNearLat_deg = 24.3;
constexpr double kHeight_m = 3000.0, kSigma_m = 35000.0;
constexpr double kFarWestOfGrid_m = 250000.0;  // the far mountain's distance beyond the grid's west edge

class DemRender : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    dir_ = std::make_unique<ScratchDir>("dem");
    datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();  // HGT = 0: a flat sea
    spec.ntimes = 1;
    data_ = dir_->file("wrfout_flat.nc");
    basemap_ = dir_->file("coded.exr");
    (void)datagen::writeWrfHurricane(spec, data_);
    writeCodedBasemap(basemap_);
    // The far mountain's lon/lat: world (−250 km, ¾ height) of the data's frame.
    {
      auto plain = open("");
      const auto& prep = plain->prepared();
      // Off the far square's centre row (a flipped far field would show) and column.
      const scene::LonLat ll = prep.geo->lonLatFromWorld({-kFarWestOfGrid_m, 0.75 * prep.frame.size_m().y});
      far_ = {ll.lon_deg, ll.lat_deg};
    }
    writeDem();
  }
  /// A lon/lat Float32 DEM, 0.02° (≈ 2 km) pixels over 88–64° W, 14–34° N: the two Gaussians.
  void writeDem() {
    constexpr double kLon0 = -88.0, kLat0 = 34.0, kPixel_deg = 0.02;
    constexpr int kW = 1200, kH = 1000;
    constexpr double kMetresPerDeg = 6370000.0 * 3.14159265358979 / 180.0;
    std::vector<double> h(std::size_t(kW) * kH);
    for (int j = 0; j < kH; ++j) {
      for (int i = 0; i < kW; ++i) {
        const double lon = kLon0 + (i + 0.5) * kPixel_deg, lat = kLat0 - (j + 0.5) * kPixel_deg;
        double z = 0.0;
        for (const glm::dvec2 c : {glm::dvec2(kNearLon_deg, kNearLat_deg), far_}) {
          const double dx = (lon - c.x) * std::cos(glm::radians(c.y)) * kMetresPerDeg, dy = (lat - c.y) * kMetresPerDeg;
          z += kHeight_m * std::exp(-(dx * dx + dy * dy) / (2.0 * kSigma_m * kSigma_m));
        }
        h[std::size_t(j) * kW + std::size_t(i)] = z;
      }
    }
    dem_ = dir_->file("dem.tif");
    scene::test::writeGeoTiff(
        dem_,
        {kW, kH, 1, GDT_Float32, std::array<double, 6>{kLon0, kPixel_deg, 0.0, kLat0, 0.0, -kPixel_deg}, "EPSG:4326"},
        h);
  }
  std::unique_ptr<engine::Session> open(const std::string& dem) const {
    const std::string json =
        R"({"data": {"path": "x"}, "camera": {"preset": "top", "fov_deg": 30},
      "sun": {"azimuth_deg": 200, "elevation_deg": 60},
      "basemap": {"path": ")" +
        basemap_ + R"(", "margin": 0.1, "pixels_long_side": 2048},
      "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
      "output": {"width": 320, "height": 240},)" +
        (dem.empty() ? std::string() : R"("terrain": {"dem": ")" + dem + R"("},)") + R"("height_exaggeration": 4})";
    return openSession(json, data_);
  }
  /// Places the summit at `lonLat` (see the header comment); returns the miss [px].
  void summitLandsAtItsProjectedPixel(glm::dvec2 lonLat, const char* which);
  std::unique_ptr<ScratchDir> dir_;
  std::string data_, basemap_, dem_;
  glm::dvec2 far_{0.0};
};

void DemRender::summitLandsAtItsProjectedPixel(glm::dvec2 lonLat, const char* which) {
  auto session = open(dem_);
  lighting::StyleSettings style = session->style();
  style.atmosphere = false;
  style.ambient = glm::dvec3(0.0);  // sunlight only: grey, so blue measures the shading
  session->setStyle(style);
  session->renderSettings().min_transmittance = 1.0;  // clouds off
  const auto& prep = session->prepared();
  ASSERT_TRUE(prep.dem);
  const volume::TerrainField terrain = volume::terrainOf(session->dataset().load(0), prep.frame, &*prep.dem);
  ASSERT_TRUE(terrain.present());
  const glm::dvec2 summitXy = prep.geo->worldFromLonLat({lonLat.x, lonLat.y});
  const double summitZ = terrain.heightAt(summitXy);
  // The DEM's 2 km pixels warped onto 10 km mass points (near) or ~4.2 km far pixels, bilinear:
  // ≥ 90 % of the Gaussian's 3000 m × 4 stays.
  EXPECT_GT(summitZ, 0.9 * 4.0 * kHeight_m) << which;
  EXPECT_LE(summitZ, 1.0001 * 4.0 * kHeight_m) << which;
  const glm::dvec3 summit(summitXy, summitZ);
  // The lon/lat must not lie near a square's edge of the coded basemap (blue constant around it).
  const double blue = codedBasemapBlue(lonLat.x, lonLat.y);
  ASSERT_EQ(codedBasemapBlue(lonLat.x - 1.0, lonLat.y - 1.0), blue);
  ASSERT_EQ(codedBasemapBlue(lonLat.x + 1.0, lonLat.y + 1.0), blue);

  scene::Camera cam = prep.flat_camera;
  const double az = glm::radians(225.0), el = glm::radians(25.0), distance_m = 150000.0;
  cam.target_m = summit + glm::dvec3(3170.0, -4310.0, -2270.0);  // neither the image centre nor a pixel centre
  cam.position_m =
      summit + distance_m * glm::dvec3(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  const glm::dvec2 expected = projectedPixel(cam, summit);
  const glm::dvec2 found = locateCodedLonLat(session->render(cam).frame, cam, lonLat, blue);
  const double miss = glm::length(found - expected);
  std::printf("[ dem] %s summit (%.1f m world) at pixel (%.3f, %.3f), projected (%.3f, %.3f): %.3f px\n", which,
              summitZ, found.x, found.y, expected.x, expected.y, miss);
  EXPECT_LE(miss, 1.5) << which;

  session->renderSettings().terrain = false;  // the bare plane: the lon/lat is far away in the image
  const glm::dvec2 flat = locateCodedLonLat(session->render(cam).frame, cam, lonLat, blue);
  std::printf("[ dem] %s: without terrain the lon/lat shows %.1f px away\n", which, glm::length(flat - expected));
  EXPECT_GT(glm::length(flat - expected), 20.0) << which;
  EXPECT_LE(glm::length(flat - projectedPixel(cam, glm::dvec3(summitXy, 0.0))), 1.5) << which;
}

TEST_F(DemRender, SummitInsideTheGridLandsAtItsProjectedPixel) {
  summitLandsAtItsProjectedPixel({kNearLon_deg, kNearLat_deg}, "near");
}

TEST_F(DemRender, SummitBeyondTheGridLandsAtItsProjectedPixel) {
  // Beyond the model's grid and its fade to the far field (a tenth of 720 km): the far field alone.
  auto session = open(dem_);
  const auto& prep = session->prepared();
  const volume::TerrainField terrain = volume::terrainOf(session->dataset().load(0), prep.frame, &*prep.dem);
  ASSERT_GT(kFarWestOfGrid_m - 3.0 * kSigma_m, terrain.fade_m);
  summitLandsAtItsProjectedPixel(far_, "far");
}

}  // namespace
}  // namespace nph::test
