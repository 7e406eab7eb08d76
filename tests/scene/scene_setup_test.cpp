// prepareScene: scene file + volumes -> frame, georeference, camera, sun, reprojected basemap.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "scene/scene_setup.h"
#include "scene/solar_position.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

/// 360×180 sRGB PNG: red = column (lon), green = row (lat), blue = 0.
std::string writeBasemap(const nph::test::ScratchDir& dir) {
  const std::string path = dir.file("map.png");
  std::vector<unsigned char> px(360 * 180 * 3);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 360; ++x) {
      const std::size_t o = (std::size_t(y) * 360 + std::size_t(x)) * 3;
      px[o] = static_cast<unsigned char>(x * 255 / 359);
      px[o + 1] = static_cast<unsigned char>(y * 255 / 179);
    }
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(360, 180, 3, OIIO::TypeDesc::UINT8)));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
  return path;
}

TEST(SceneSetup, FlatSceneWithBasemapAndTimedSun) {
  nph::test::ScratchDir dir("scene");
  writeBasemap(dir);
  std::ofstream(dir.file("scene.json")) << R"({
    "camera": {"preset": "overview"},
    "sun": {"from_time": true},
    "basemap": {"path": "map.png", "margin": 0.25, "pixels_long_side": 300},
    "output": {"width": 640, "height": 360},
    "height_exaggeration": 5,
    "lonlat_offset_deg": [0.5, 0]
  })";
  const SceneDescription s = loadSceneFile(dir.file("scene.json"));
  const auto v = test::lambertVolumes();  // time 2026-09-01T12:00:00Z, centred at (−80, 25)
  const PreparedScene p = prepareScene(s, v);
  EXPECT_EQ(p.frame.height_exaggeration, 5.0);
  EXPECT_EQ(p.frame.voxel_size_m.z, 2500.0);
  ASSERT_TRUE(p.geo);
  EXPECT_NEAR(p.geo->footprintCentre().lon_deg, -79.5, 1e-9);  // offset applied
  const Camera expected = cameraFor(s.camera, p.frame, 640, 360);
  EXPECT_EQ(p.camera.position_m, expected.position_m);
  EXPECT_EQ(p.camera.width, 640);
  const SolarPosition sp = solarPosition(UtcTime::parse("2026-09-01T12:00:00Z"), -79.5, 25.0);
  EXPECT_NEAR(p.sun.elevation_deg, sp.elevation_deg, 1e-6);
  EXPECT_FALSE(p.to_sun_ecef);
  // Basemap: 300 px on the long side of the 450 km × 390 km rectangle.
  ASSERT_TRUE(p.basemap_rect);
  EXPECT_EQ(p.basemap.width, 300);
  EXPECT_EQ(p.basemap.height, 260);
  // The centre pixel shows the map at the footprint centre (as shown, offset included).
  const glm::vec3 c = p.basemap.at(150, 130);
  const EquirectangularImage src = EquirectangularImage::load(dir.file("map.png"));
  const glm::dvec2 w = worldFromBasemapPixel(*p.basemap_rect, 300, 260, 150, 130);
  const LonLat ll = p.geo->lonLatFromWorld(w);
  const glm::vec3 e = src.sampleLonLat(ll.lon_deg, ll.lat_deg);
  // The PNG's 8-bit codes are interpolated by GDAL's warper and then decoded (scene/basemap.h), the
  // reference decodes and then interpolates: they differ by the sRGB curve's curvature over the
  // neighbouring codes, f''·Δ²/8 < 1e-5 for this smooth map (3.5e-6 measured).
  EXPECT_NEAR(c.r, e.r, 1e-5f);
  EXPECT_NEAR(c.g, e.g, 1e-5f);
  EXPECT_GT(c.r, 0.0f);
}

TEST(SceneSetup, GlobeView) {
  const SceneDescription s = parseSceneText(R"({"view": "globe", "sun": {"from_time": true}})", "g.json");
  const auto v = test::lambertVolumes();
  const PreparedScene p = prepareScene(s, v);
  EXPECT_NEAR(glm::length(p.camera.target_m), volume::kEarthRadius_m + p.flat_camera.target_m.z, 1e-3);
  ASSERT_TRUE(p.to_sun_ecef);
  EXPECT_NEAR(glm::length(*p.to_sun_ecef - sunDirectionEcef(*v.time_utc)), 0.0, 1e-6);
}

TEST(SceneSetup, CartesianGridsNeedACentreForMapsAndTimedSuns) {
  ExtinctionVolumes v;
  v.nx = v.ny = 10;
  v.nz = 2;
  v.dz_m = 100.0;
  v.georef.dx_m = v.georef.dy_m = 1000.0;
  v.time_utc = nph::geo::UtcTime::parse("2026-09-01T12:00:00Z");
  EXPECT_NO_THROW(prepareScene(parseSceneText("{}", "s.json"), v));
  EXPECT_THROW(prepareScene(parseSceneText(R"({"sun": {"from_time": true}})", "s.json"), v), InputError);
  EXPECT_THROW(prepareScene(parseSceneText(R"({"view": "globe"})", "s.json"), v), InputError);
  EXPECT_THROW(prepareScene(parseSceneText(R"({"basemap": {"path": "/x.jpg"}})", "s.json"), v), InputError);
  const PreparedScene p =
      prepareScene(parseSceneText(R"({"sun": {"from_time": true}, "centre_lonlat_deg": [10, 50]})", "s.json"), v);
  EXPECT_NEAR(p.sun.elevation_deg, solarPosition(*v.time_utc, 10.0, 50.0).elevation_deg, 1e-6);
  // A missing basemap file is reported with its name.
  try {
    (void)prepareScene(
        parseSceneText(R"({"basemap": {"path": "/no/such/map.jpg"}, "centre_lonlat_deg": [10, 50]})", "s.json"), v);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/map.jpg"), std::string::npos) << e.what();
  }
}

TEST(SceneSetup, TimestepByIndexOrTime) {
  const std::vector<geo::OptionalUtcTime> times = {UtcTime::parse("2026-09-01T12:00:00Z"),
                                                   UtcTime::parse("2026-09-01T13:00:00Z"),
                                                   UtcTime::parse("2026-09-01T14:00:00Z")};
  DataSpec d;
  d.timestep = 2;
  EXPECT_EQ(timestepIndexFor(d, times, "h.nph"), 2u);
  d.time_utc = "2026-09-01_13:00:00";
  EXPECT_EQ(timestepIndexFor(d, times, "h.nph"), 1u);
  d.time_utc = "2026-09-01T13:30:00Z";
  try {
    (void)timestepIndexFor(d, times, "h.nph");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("h.nph: no timestep at 2026-09-01T13:30:00Z (the file has 3 timesteps, "
                                         "2026-09-01T12:00:00Z to 2026-09-01T14:00:00Z)"),
              std::string::npos)
        << e.what();
  }
  d.time_utc.reset();
  d.timestep = 3;
  EXPECT_THROW(timestepIndexFor(d, times, "h.nph"), InputError);
}

}  // namespace
}  // namespace nph::scene
