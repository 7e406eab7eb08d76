// City lights on the night side through the renderer (issue 14 item 3; glsl/common/night_lights.glsl).
// The chain under test is the scene's basemap.night_lights raster → GDAL warp onto the basemap's
// grids (scene_setup.cpp) → scene::cityLightsIntensity → the imagery textures' A channel → the eye
// pass's ground (glsl/render/clouds.comp) → the frame.
//
// The lights raster is a whole-Earth EXR, white (1, 1, 1) in a 1° checkerboard of lon/lat and
// black elsewhere, so each pixel's ground point (the CPU's ray–plane or ray–sphere hit, terrain off)
// says whether it lies over lit or dark ground. The knob city_lights switches the lights:
// 1. Night, clear sky (flat view, sun 10° below the horizon, atmosphere off so the closed form is
//    exact): over a lit square the frame gains exactly cityLightsRadiance(I(white), sin(−10°), E, k)
//    (the CPU twin of the shader's function); over a dark square it gains nothing.
// 2. Night, under cloud (α from 0.2 to 0.98, the thick eyewall included): the gain is the clear-sky gain times the
// cloud's transmittance: the GPU
//    layer's own 1 − α to float rounding, and the CPU's exact e^{−τ} of the ray to the ground
//    (reference::ExtinctionField) within the eye pass's quadrature error.
// 3. Day (sun 30° up): the switch changes no bit of any pixel, in the flat view and on the globe's
//    day side; on the globe's night side (same frame) the lit squares gain light.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "reference/path_tracer_field.h"
#include "render_scenes.h"
#include "scene/night_lights.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

constexpr double kSquare_deg = 1.0;  // the lights' checkerboard
constexpr float kLightsKnob = 0.05f;

// Whether lon/lat lies in a lit square, and its distance to the nearest square edge [deg].
bool litSquare(double lon_deg, double lat_deg, double& edge_deg) {
  const double a = (lon_deg + 180.0) / kSquare_deg, b = (90.0 - lat_deg) / kSquare_deg;
  edge_deg = kSquare_deg * std::min({a - std::floor(a), std::ceil(a) - a, b - std::floor(b), std::ceil(b) - b});
  return (static_cast<long>(std::floor(a)) + static_cast<long>(std::floor(b))) % 2 != 0;
}

// 1440 × 720 (0.25° per pixel): 4 pixels per square.
void writeCheckerLights(const std::string& path) {
  constexpr int kW = 1440, kH = 720;
  std::vector<float> rgb(std::size_t(kW) * kH * 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      double edge = 0.0;
      const bool lit = litSquare(-180.0 + (x + 0.5) * 360.0 / kW, 90.0 - (y + 0.5) * 180.0 / kH, edge);
      for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * kW + std::size_t(x)) * 3 + std::size_t(c)] = lit ? 1.0f : 0.0f;
    }
  }
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(kW, kH, 3, OIIO::TypeDesc::HALF);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close()) {
    throw std::runtime_error("writeCheckerLights: " + path);
  }
}

class NightLights : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    dir_ = std::make_unique<ScratchDir>("night-lights");
    data_ = dir_->file("wrfout_storm.nc");
    basemap_ = dir_->file("coded.exr");
    lights_ = dir_->file("lights.exr");
    datagen::writeWrfHurricane(smallStormSpec(), data_);
    writeCodedBasemap(basemap_);
    writeCheckerLights(lights_);
  }
  std::unique_ptr<engine::Session> open(double sun_elevation_deg, const std::string& view) const {
    const std::string json = R"({"data": {"path": "x"}, "camera": {"preset": "top", "fov_deg": 40},
      "sun": {"azimuth_deg": 200, "elevation_deg": )" +
                             std::to_string(sun_elevation_deg) + R"(},
      "basemap": {"path": ")" +
                             basemap_ + R"(", "night_lights": ")" + lights_ +
                             R"(", "margin": 0.1, "pixels_long_side": 1024},
      "style": {"atmosphere": false, "terrain": false, "city_lights": )" +
                             std::to_string(kLightsKnob) + R"(},
      "output": {"width": 160, "height": 120}, "height_exaggeration": 4, "view": ")" +
                             view + R"("})";
    return openSession(json, data_);
  }
  // Renders the session's camera with the lights at `k`.
  static render::RenderOutput renderWith(engine::Session& session, double k) {
    session.renderSettings().city_lights = k;
    return session.render(session.prepared().camera);
  }
  std::unique_ptr<ScratchDir> dir_;
  std::string data_, basemap_, lights_;
};

std::size_t rgbaIndex(const scene::Camera& cam, int x, int y) {
  return (std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4;
}

TEST_F(NightLights, LightUpLitGroundByTheirRadianceAndAreDimmedByTheCloudsTransmittance) {
  auto session = open(-10.0, "flat");
  const auto& prep = session->prepared();
  const scene::Camera& cam = prep.camera;
  const render::RenderOutput on = renderWith(*session, kLightsKnob), off = renderWith(*session, 0.0);
  const ExtinctionVolumes volumes = session->dataset().load(0);
  const reference::ExtinctionField field(volumes, session->volumeTextures().frame(),
                                         session->volumeTextures().reconstruction());

  const float white = scene::cityLightsIntensity({1, 1, {1.0f, 1.0f, 1.0f}}).front();
  const glm::vec3 sun = glm::vec3(prep.sun.colour * prep.sun.intensity);
  const glm::vec3 expected = scene::cityLightsRadiance(white, float(std::sin(glm::radians(-10.0))), sun, kLightsKnob);
  ASSERT_GT(expected.g, 0.0f);
  int clearLit = 0, clearDark = 0, cloudy = 0;
  double worstClearLit = 0.0, worstDark = 0.0, worstAlpha = 0.0, worstTau = 0.0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
      if (d.z >= 0.0) continue;
      const double t = -cam.position_m.z / d.z;  // the plane z = 0 (terrain off)
      const geo::LonLat ll = prep.geo->lonLatFromWorld(glm::dvec2(cam.position_m + t * d));
      double edge = 0.0;
      const bool lit = litSquare(ll.lon_deg, ll.lat_deg, edge);
      if (edge < 0.35) continue;  // the warp's and the mipmaps' blur at the squares' edges
      const std::size_t o = rgbaIndex(cam, x, y);
      const double alpha = on.cloud_layer.rgba[o + 3];
      for (int c = 0; c < 3; ++c) {
        const double gain = double(on.frame.rgba[o + std::size_t(c)]) - double(off.frame.rgba[o + std::size_t(c)]);
        const double clear = double(expected[c]);
        if (alpha < 1e-5) {
          if (lit) {
            worstClearLit = std::max(worstClearLit, std::abs(gain / clear - 1.0));
          } else {
            worstDark = std::max(worstDark, std::abs(gain) / clear);
          }
        } else if (lit && alpha > 0.2 && alpha < 0.98) {
          worstAlpha = std::max(worstAlpha, std::abs(gain / clear - (1.0 - alpha)));
          if (c == 0) {
            const double T = std::exp(-field.opticalDepth(cam.position_m, d, 0.0, t));
            worstTau = std::max(worstTau, std::abs(gain / clear - T));
          }
        }
      }
      if (alpha < 1e-5) ++(lit ? clearLit : clearDark);
      if (lit && alpha > 0.2 && alpha < 0.98) ++cloudy;
    }
  }
  std::printf("[ lights] clear sky: %d lit pixels gain the closed form to %.2e (relative), %d dark ones %.2e; "
              "%d lit pixels under cloud (0.2 < alpha < 0.98): gain/clear = 1 - alpha to %.2e, = exp(-tau) "
              "(CPU) to %.4f\n",
              clearLit, worstClearLit, clearDark, worstDark, cloudy, worstAlpha, worstTau);
  ASSERT_GT(clearLit, 100) << "the view must show clear lit ground";
  ASSERT_GT(clearDark, 100) << "the view must show clear dark ground";
  ASSERT_GT(cloudy, 50) << "the view must show lit ground under cloud";
  EXPECT_LT(worstClearLit, 1e-3);
  EXPECT_LT(worstDark, 1e-4);
  EXPECT_LT(worstAlpha, 1e-3);
  // The eye pass's jittered half-voxel steps against the CPU's exact integral (the terrain test's
  // occlusion allows 0.02 on α for the same quadrature).
  EXPECT_LT(worstTau, 0.03);
}

TEST_F(NightLights, ChangeNoBitOnTheDaySide) {
  auto flat = open(30.0, "flat");
  const render::RenderOutput on = renderWith(*flat, kLightsKnob), off = renderWith(*flat, 0.0);
  ASSERT_EQ(on.frame.rgba.size(), off.frame.rgba.size());
  EXPECT_EQ(0, std::memcmp(on.frame.rgba.data(), off.frame.rgba.data(), on.frame.rgba.size() * sizeof(float)))
      << "flat view, sun 30° up: the lights switch changed pixels";

  // The globe with the terminator across the view: the sun 1° below the horizon at the footprint
  // centre, so the day side begins ~110 km away towards the sun.
  auto globe = open(-1.0, "globe");
  const auto& prep = globe->prepared();
  const scene::Camera& cam = prep.camera;
  const render::RenderOutput gOn = renderWith(*globe, kLightsKnob), gOff = renderWith(*globe, 0.0);
  const glm::dvec3 toSun = *prep.to_sun_ecef;
  const glm::vec3 sun = glm::vec3(prep.sun.colour * prep.sun.intensity);
  int day = 0, changedDay = 0, nightLit = 0, brighterNightLit = 0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5), o = cam.position_m;
      const double b = glm::dot(o, d), c = glm::dot(o, o) - volume::kEarthRadius_m * volume::kEarthRadius_m;
      if (b * b - c < 0.0) continue;
      const glm::dvec3 g = o + (-b - std::sqrt(b * b - c)) * d;  // the sphere R (terrain off)
      const double sinSun = glm::dot(glm::normalize(g), toSun);
      const std::size_t i = rgbaIndex(cam, x, y);
      if (sinSun > 0.005) {  // clear of the float rounding of the GPU's sun elevation at 0
        ++day;
        if (std::memcmp(&gOn.frame.rgba[i], &gOff.frame.rgba[i], 3 * sizeof(float)) != 0) ++changedDay;
        continue;
      }
      const double lat = glm::degrees(std::atan2(g.z, std::hypot(g.x, g.y))), lon = glm::degrees(std::atan2(g.y, g.x));
      double edge = 0.0;
      if (sinSun < -0.02 && litSquare(lon, lat, edge) && edge > 0.4 && gOn.cloud_layer.rgba[i + 3] < 0.5f) {
        // At least a tenth of the lights' closed form at full intensity: the globe's imagery (the
        // coded basemap's 0.5° grid) blurs the 1° squares, the cloud in front takes up to half.
        const float full = scene::cityLightsRadiance(1.0f, float(sinSun), sun, float(kLightsKnob)).g;
        ++nightLit;
        if (gOn.frame.rgba[i + 1] - gOff.frame.rgba[i + 1] > 0.1f * full) ++brighterNightLit;
      }
    }
  }
  std::printf("[ lights] globe: %d day-side pixels, %d changed; %d lit night-side pixels, %d brighter\n", day,
              changedDay, nightLit, brighterNightLit);
  EXPECT_GT(day, 1000);
  EXPECT_EQ(changedDay, 0);
  EXPECT_GT(nightLit, 50);
  EXPECT_EQ(brighterNightLit, nightLit);
}

}  // namespace
}  // namespace nph::test
