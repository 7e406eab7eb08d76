// Placement through the renderer (issue 5 "Done means"): a generated storm whose centre the
// generator put at a known lon/lat appears at that pixel of the rendered image — top camera over
// the basemap, flat view, Lambert and Mercator wrfout files. The truth is the generator's own
// XLAT/XLONG (its own PROJ set-up) at the storm centre; the chain under test is wrfout -> loader ->
// optics -> Dataset/Session -> georeference -> camera -> GPU ray caster and basemap.
// Two checks per projection:
//   1. The clouds are where the data puts them: the GPU layer's α at every pixel is 1 − e^{−τ} of
//      the exact optical depth of that pixel's camera ray through the same volumes (measured max
//      |diff| 0.0100, the renormalised early termination's T_min, over ~2600 edge pixels).
//   2. The basemap drawn at that pixel is the one of the storm's lon/lat: with the clouds off
//      (transmittance threshold 1: no ray marches), the frame's colour there decodes (lon/lat-coded
//      basemap) to the truth within 0.05° (the nearest pixel centre is up to 0.7 px ≈ 0.015° away; measured 0.012°).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "lighting/cloud_light.h"
#include "reference/path_tracer_field.h"
#include "render_scenes.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

glm::dvec2 pixelOf(const scene::Camera& cam, const glm::dvec3& world) {
  const glm::dvec4 clip = cam.clipFromView() * cam.viewFromWorld() * glm::dvec4(world, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {0.5 * (ndc.x + 1.0) * cam.width, 0.5 * (1.0 - ndc.y) * cam.height};  // continuous, y down
}

[[maybe_unused]] double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
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
    "basemap": {"path": ")" +
                           basemap + R"(", "margin": 0.1, "pixels_long_side": 1024},
    "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
    "output": {"width": 320, "height": 240}, "height_exaggeration": 1, "view": "flat"})";
  auto session = openSession(json, data);
  // The frame's colour decodes the coded basemap: no aerial perspective or sky light over it.
  lighting::StyleSettings style = session->style();
  style.atmosphere = false;
  session->setStyle(style);
  const auto& prep = session->prepared();
  const scene::Camera& cam = prep.camera;

  const scene::LonLat stormLl = stormCentreLonLat(truth, spec);
  const glm::dvec2 stormXy = prep.geo->worldFromLonLat(stormLl);
  const glm::dvec2 bottom = pixelOf(cam, {stormXy, prep.frame.min_m().z});
  [[maybe_unused]] const glm::dvec2 top = pixelOf(cam, {stormXy, prep.frame.max_m().z});

  // 1. The clouds where the data puts them: every pixel's GPU α equals 1 − e^{−τ} of the exact
  // optical depth of the same camera ray through the same volumes (the path tracer's integral, in
  // double), over the whole image — storm edges included, where a shift of the volume by a pixel
  // changes α by far more than the bound. (Until issue 12 this part located the eye as the centroid
  // of the layer's transparency; the generated eye is not clear air — τ ≈ 15–20 down its column,
  // float α = 1 — and that centroid was only ever the window's centre, through the 1 % that early
  // termination left transparent.) The bound: 0.01 of renormalised early termination (T_min) plus
  // the ½-voxel march's quadrature error at the edges.
  const auto out = session->render(cam);
  const ExtinctionVolumes volumes = session->dataset().load(0);
  const reference::ExtinctionField field(volumes, session->volumeTextures().frame(),
                                         session->volumeTextures().reconstruction());
  double alphaErr = 0.0;
  int edges = 0, cloudy = 0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const double tau = field.opticalDepth(cam.position_m, cam.rayDirection(x + 0.5, y + 0.5), 0.0, 1e300);
      const double exact = -std::expm1(-tau);
      const double a = out.cloud_layer.rgba[(std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4 + 3];
      alphaErr = std::max(alphaErr, std::abs(a - exact));
      edges += exact > 0.1 && exact < 0.9;
      cloudy += exact >= 0.9;
    }
  }
  std::printf("[ placement] GPU alpha vs exact optical depth: max |diff| %.4f over %d edge and %d cloudy pixels\n",
              alphaErr, edges, cloudy);
  EXPECT_GT(edges, 50) << "the storm's edges must be in view";
  EXPECT_GT(cloudy, 1000) << "the storm must be in view";
  EXPECT_LT(alphaErr, 0.03);

  // 2. The basemap under it, clouds off.
  session->renderSettings().min_transmittance = 1.0;
  session->renderSettings().shadows = false;
  const auto ground = session->render(cam);
  const int px = int(bottom.x), py = int(bottom.y);
  const std::size_t o = (std::size_t(py) * std::size_t(cam.width) + std::size_t(px)) * 4;
  const double cosSun = std::sin(glm::radians(60.0));
  const auto& rs = session->renderSettings();
  const glm::dvec3 sky = lighting::skyLightFor(rs, 60.0, glm::dvec3(1.0), 1.0).above;
  const glm::dvec3 light = (glm::dvec3(cosSun) + std::numbers::pi * sky) / std::numbers::pi;  // ρ/π·(E cos θ + π L_sky)
  double lon = 0.0, lat = 0.0;
  decodeBasemapColour(float(double(ground.frame.rgba[o]) / light.r), float(double(ground.frame.rgba[o + 1]) / light.g),
                      lon, lat);
  std::printf("[ placement] basemap at that pixel: %.4f, %.4f (truth %.4f, %.4f)\n", lon, lat, stormLl.lon_deg,
              stormLl.lat_deg);
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
