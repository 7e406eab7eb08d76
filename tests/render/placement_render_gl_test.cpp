// Placement through the renderer (issue 5 "Done means"): a generated storm whose centre the
// generator put at a known lon/lat appears at that pixel of the rendered image — top camera over
// the basemap, flat view, Lambert and Mercator wrfout files. The truth is the generator's own
// XLAT/XLONG (its own PROJ set-up) at the storm centre; the chain under test is wrfout -> loader ->
// optics -> Dataset/Session -> georeference -> camera -> GPU ray caster and basemap.
// Two checks per projection:
//   1. The eye (clear within 14 km of the centre, eyewall at 40 km) is where the truth projects:
//      the (1 − α)-weighted centroid of the cloud layer within 25 km lies on the segment between
//      the projections of the centre at the volume's bottom and top (the eye is a vertical column
//      seen in perspective) to within 1.5 pixels (1 pixel ≈ 2.4 km here; measured 0.14 px).
//   2. The basemap drawn at that pixel is the one of the storm's lon/lat: with the clouds off
//      (transmittance threshold 1: no ray marches), the frame's colour there decodes (lon/lat-coded
//      basemap) to the truth within 0.05° (the nearest pixel centre is up to 0.7 px ≈ 0.015° away; measured 0.012°).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render_scenes.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

glm::dvec2 pixelOf(const scene::Camera& cam, const glm::dvec3& world) {
  const glm::dvec4 clip = cam.clipFromView() * cam.viewFromWorld() * glm::dvec4(world, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {0.5 * (ndc.x + 1.0) * cam.width, 0.5 * (1.0 - ndc.y) * cam.height};  // continuous, y down
}

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double t = glm::dot(ab, ab) > 0.0 ? glm::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

class RenderedPlacement : public GlTest, public ::testing::WithParamInterface<datagen::WrfProjection> {};

TEST_P(RenderedPlacement, StormAppearsAtItsLonLatPixel) {
  ScratchDir dir("placement");
  const datagen::WrfHurricaneSpec spec = smallStormSpec(GetParam());
  const std::string data = dir.file("wrfout.nc"), basemap = dir.file("coded.exr");
  const datagen::WrfTruth truth = datagen::writeWrfHurricane(spec, data);
  writeCodedBasemap(basemap);
  const std::string json = R"({"data": {"path": "x"}, "camera": {"preset": "top", "fov_deg": 40},
    "sun": {"azimuth_deg": 180, "elevation_deg": 60},
    "basemap": {"path": ")" + basemap + R"(", "margin": 0.1, "pixels_long_side": 1024},
    "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
    "output": {"width": 320, "height": 240}, "height_exaggeration": 1, "view": "flat"})";
  auto session = openSession(json, data);
  const auto& prep = session->prepared();
  const scene::Camera& cam = prep.camera;

  const scene::LonLat stormLl = stormCentreLonLat(truth, spec);
  const glm::dvec2 stormXy = prep.geo->worldFromLonLat(stormLl);
  const glm::dvec2 bottom = pixelOf(cam, {stormXy, prep.frame.min_m().z});
  const glm::dvec2 top = pixelOf(cam, {stormXy, prep.frame.max_m().z});

  // 1. The eye in the cloud layer.
  const auto out = session->render(cam);
  const double pixel_m = 2.0 * glm::length(cam.position_m - cam.target_m) *
                         std::tan(glm::radians(0.5 * cam.vertical_fov_deg)) / cam.height;
  const double window_px = 25000.0 / pixel_m;
  glm::dvec2 sum(0.0);
  double weight = 0.0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec2 c(x + 0.5, y + 0.5);
      if (glm::length(c - bottom) > window_px) continue;
      const double a = out.cloud_layer.rgba[(std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4 + 3];
      sum += (1.0 - a) * c;
      weight += 1.0 - a;
    }
  }
  ASSERT_GT(weight, 1.0) << "no clear eye near the expected pixel";
  const glm::dvec2 eye = sum / weight;
  const double miss = distanceToSegment(eye, bottom, top);
  std::printf("[ placement] storm at %.3f, %.3f: expected pixel (%.1f, %.1f)-(%.1f, %.1f), eye at (%.1f, %.1f), %.2f px off (pixel %.2f km)\n",
              stormLl.lon_deg, stormLl.lat_deg, bottom.x, bottom.y, top.x, top.y, eye.x, eye.y, miss, pixel_m / 1000.0);
  EXPECT_LT(miss, 1.5);

  // 2. The basemap under it, clouds off.
  session->renderSettings().min_transmittance = 1.0;
  const auto ground = session->render(cam);
  const int px = int(bottom.x), py = int(bottom.y);
  const std::size_t o = (std::size_t(py) * std::size_t(cam.width) + std::size_t(px)) * 4;
  const double cosSun = std::sin(glm::radians(60.0));
  const glm::dvec3 light = glm::dvec3(cosSun) + session->renderSettings().ambient;
  double lon = 0.0, lat = 0.0;
  decodeBasemapColour(float(double(ground.frame.rgba[o]) / light.r), float(double(ground.frame.rgba[o + 1]) / light.g), lon, lat);
  std::printf("[ placement] basemap at that pixel: %.4f, %.4f (truth %.4f, %.4f)\n", lon, lat, stormLl.lon_deg, stormLl.lat_deg);
  EXPECT_NEAR(lon, stormLl.lon_deg, 0.05);
  EXPECT_NEAR(lat, stormLl.lat_deg, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Wrf, RenderedPlacement,
                         ::testing::Values(datagen::WrfProjection::Lambert, datagen::WrfProjection::Mercator),
                         [](const auto& param) {
                           return std::string(param.param == datagen::WrfProjection::Lambert ? "Lambert" : "Mercator");
                         });

}  // namespace
}  // namespace nph::test
