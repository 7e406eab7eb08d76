// Globe view (render/raycast/globe.h): the lon/lat -> world table against PROJ, and empty-space
// skipping under the curved mapping changes nothing (its jumps are conservative).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <OpenImageIO/imageio.h>

#include "render/raycast/globe.h"
#include "render_scenes.h"
#include "scene/basemap.h"
#include "support/gl_fixture.h"
#include "support/image_compare.h"

namespace nph::test {
namespace {

struct GlobeScene {
  ScratchDir dir{"globe"};
  std::string data = dir.file("wrfout.nc"), basemap = dir.file("coded.exr");
  GlobeScene() {
    datagen::writeWrfHurricane(smallStormSpec(), data);
    writeCodedBasemap(basemap);
  }
  std::unique_ptr<engine::Session> session(const std::string& preset) const {
    return openSession(R"({"data": {"path": "x"}, "camera": {"preset": ")" + preset + R"(", "fov_deg": 40},
      "sun": {"azimuth_deg": 100, "elevation_deg": 25},
      "basemap": {"path": ")" +
                           basemap + R"(", "margin": 0.4, "pixels_long_side": 256},
      "quality": {"preset": "broadcast"}, "output": {"width": 160, "height": 90},
      "height_exaggeration": 8, "view": "globe"})",
                       data);
  }
};

const GlobeScene& globeScene() {
  static const GlobeScene s;
  return s;
}

using GlobeTest = GlTest;

// The table reproduces the exact transform (PROJ) to interpolation error: every world point of
// the footprint, carried onto the globe and back through the table, lands within 2 m (0.04 % of a
// 5 km voxel) of where it started.
TEST_F(GlobeTest, TableMatchesTheExactTransform) {
  auto s = globeScene().session("overview");
  const scene::SceneGeoreference& geo = *s->prepared().geo;
  const render::GlobeMapping m = render::buildGlobeMapping(geo);
  const glm::dvec3 size = s->prepared().frame.size_m();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double maxErr = 0.0;
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 w{u(rng) * size.x, u(rng) * size.y, u(rng) * size.z};
    const glm::dvec2 back = render::worldXyFromTable(m, geo.ecefFromWorld(w));
    maxErr = std::max(maxErr, glm::length(back - glm::dvec2(w)));
  }
  std::printf("[ globe    ] table %dx%d: round trip max %.3f m, interpolation error %.3f m, L_h %.4f\n", m.width,
              m.height, maxErr, m.max_interpolation_error_m, m.horizontal_lipschitz);
  EXPECT_LT(maxErr, 2.0);
  EXPECT_LT(m.max_interpolation_error_m, 2.0);
  EXPECT_GT(m.horizontal_lipschitz, 0.9);  // a conformal map of a sphere onto itself: about 1
  EXPECT_LT(m.horizontal_lipschitz, 1.1);
}

// Skipping empty bricks on the globe jumps whole steps of the jittered lattice over ECEF distances
// that provably stay in empty space; with it on and off the same samples see cloud, so the frames
// agree but for the rounding of t accumulated over different numbers of additions (sample
// positions move by ~1e-7 of the distance: far below a voxel).
TEST_F(GlobeTest, EmptySpaceSkippingChangesNothing) {
  for (const char* preset : {"oblique"}) {  // the storm seen over the curved horizon
    auto s = globeScene().session(preset);
    const scene::Camera cam = s->prepared().camera;
    s->renderSettings().empty_space_skipping = true;
    const auto on = s->render(cam);
    s->renderSettings().empty_space_skipping = false;
    const auto off = s->render(cam);
    Image a{on.cloud_layer.width, on.cloud_layer.height, 4, on.cloud_layer.rgba};
    Image b{off.cloud_layer.width, off.cloud_layer.height, 4, off.cloud_layer.rgba};
    double coverage = 0.0;
    for (std::size_t i = 3; i < b.pixels.size(); i += 4) coverage += double(b.pixels[i]);
    coverage /= double(b.pixels.size() / 4);
    const CompareResult r = compareImages(a, b, {2e-3, 1e-5}, std::string("globe-skipping-") + preset);
    std::printf("[ globe    ] %s: coverage %.2f, skipping on vs off: max %.2e, mean %.2e\n", preset, coverage,
                r.max_abs, r.mean_abs);
    EXPECT_GT(coverage, 0.02) << "the camera must see the storm";
    EXPECT_TRUE(r.pass) << r.message;

    // ... and it does skip: fewer volume samples with it on (same volume, DLM and rays; this storm's
    // deck fills its box, so only the few % of samples above it and outside the footprint go).
    render::CloudRenderer renderer;
    const glm::dvec3 size = s->prepared().frame.size_m();
    renderer.setGlobe(render::buildGlobeMapping(*s->prepared().geo), {},
                      scene::toSunEcef(s->sun(), *s->prepared().geo, {0.5 * size.x, 0.5 * size.y}));
    renderer.countSamples(true);
    std::uint64_t samples[2] = {0, 0};
    for (int skip = 0; skip < 2; ++skip) {
      render::RenderSettings rs = s->renderSettings();
      rs.empty_space_skipping = skip != 0;
      renderer.render(s->volumeTextures(), s->deepLightMap(), cam, s->sun(), rs);
      samples[skip] = renderer.sampleCount();
    }
    std::printf("[ globe    ] %s: %llu volume samples without skipping, %llu with\n", preset,
                static_cast<unsigned long long>(samples[0]), static_cast<unsigned long long>(samples[1]));
    EXPECT_LT(samples[1], samples[0]);
  }
}

// Issue 14 item 3: the globe's imagery is filtered over each pixel's footprint (mipmaps and
// anisotropic taps, glsl/common/imagery.glsl), so the ground far away and towards the limb does
// not alias. Ground truth: a CPU box filter of the same texture over the pixel (16 × 16 rays
// through the pixel's area, each meeting the sphere, bilinear look-ups at their lon/lat).
// The basemap is a whole-Earth checkerboard of 2-texel cells (2048 × 1024: cells of 0.35°,
// ≈ 39 km) with albedo 0.1 / 0.9; a second render with a uniform 0.5 basemap divides the
// lighting out, so each ground pixel's albedo as the GPU filtered it is 0.5 · checker / uniform.
// The pixels tested are those whose footprint covers at least 16 cells (the box filter's rays
// land in ≥ 16 distinct cells): there the unfiltered look-up of before (one bilinear tap at the
// pixel centre) is essentially a coin toss between 0.1 and 0.9.
void writeCheckerBasemap(const std::string& path, bool uniform) {
  constexpr int kW = 2048, kH = 1024, kCell = 2;
  std::vector<float> rgb(std::size_t(kW) * kH * 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const float a = uniform ? 0.5f : (((x / kCell + y / kCell) % 2) != 0 ? 0.9f : 0.1f);
      for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * kW + std::size_t(x)) * 3 + std::size_t(c)] = a;
    }
  }
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(kW, kH, 3, OIIO::TypeDesc::FLOAT);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close()) {
    throw std::runtime_error("writeCheckerBasemap: " + path);
  }
}

TEST_F(GlobeTest, ImageryIsFilteredOverThePixelFootprint) {
  ScratchDir dir("globe-imagery");
  const std::string checker = dir.file("checker.exr"), uniform = dir.file("uniform.exr");
  writeCheckerBasemap(checker, false);
  writeCheckerBasemap(uniform, true);
  auto scene = [&](const std::string& basemap) {
    return R"({"data": {"path": "x"}, "camera": {"preset": "oblique", "fov_deg": 40, "distance_scale": 24},
      "sun": {"azimuth_deg": 100, "elevation_deg": 60},
      "basemap": {"path": ")" +
           basemap + R"(", "margin": 0.4, "pixels_long_side": 256},
      "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
      "output": {"width": 160, "height": 90}, "height_exaggeration": 8, "view": "globe"})";
  };
  auto render = [&](const std::string& basemap, scene::LinearRgbImage* equirect, scene::Camera* camera) {
    auto s = openSession(scene(basemap), globeScene().data);
    lighting::StyleSettings style = s->style();
    style.atmosphere = false;  // the ground's albedo times the light, nothing added in front
    s->setStyle(style);
    if (equirect) *equirect = s->prepared().basemap_equirect;
    if (camera) *camera = s->prepared().camera;
    return s->render(s->prepared().camera);
  };
  scene::LinearRgbImage texture;
  scene::Camera camera;
  const render::RenderOutput a = render(checker, &texture, &camera), b = render(uniform, nullptr, nullptr);
  ASSERT_EQ(texture.width, 2048) << "the checker must reach the globe at its own size";
  const scene::EquirectangularImage lookup(texture, "checker");

  const double R = scene::kEarthRadius_m;
  auto groundHit = [&](const glm::dvec3& d, glm::dvec3& g) {
    const glm::dvec3 o = camera.position_m;
    const double bq = glm::dot(o, d), c = glm::dot(o, o) - R * R, disc = bq * bq - c;
    if (disc < 0.0 || -bq - std::sqrt(disc) < 0.0) return false;
    g = o + (-bq - std::sqrt(disc)) * d;
    return true;
  };
  auto albedoAt = [&](const glm::dvec3& g, int* cell) {
    const double lon = glm::degrees(std::atan2(g.y, g.x)), lat = glm::degrees(std::asin(g.z / glm::length(g)));
    if (cell) {
      const glm::dvec2 uv = scene::equirectUv(lon, lat);
      *cell = int(std::floor(uv.x * 1024.0)) * 4096 + int(std::floor(uv.y * 512.0));
    }
    return double(lookup.sampleLonLat(lon, lat).g);
  };
  constexpr int kSub = 16;
  int tested = 0;
  double gpuErr = 0.0, pointErr = 0.0, gpuSq = 0.0, pointSq = 0.0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const std::size_t i = (std::size_t(y) * std::size_t(camera.width) + std::size_t(x)) * 4;
      if (a.cloud_layer.rgba[i + 3] > 0.0f || b.cloud_layer.rgba[i + 3] > 0.0f || b.frame.rgba[i + 1] < 1e-3f) continue;
      double box = 0.0;
      std::vector<int> cells;
      bool allHit = true;
      glm::dvec3 g;
      for (int sy = 0; sy < kSub && allHit; ++sy) {
        for (int sx = 0; sx < kSub && allHit; ++sx) {
          allHit = groundHit(camera.rayDirection(x + (sx + 0.5) / kSub, y + (sy + 0.5) / kSub), g);
          int cell = 0;
          if (allHit) box += albedoAt(g, &cell);
          cells.push_back(cell);
        }
      }
      std::sort(cells.begin(), cells.end());
      if (!allHit || std::unique(cells.begin(), cells.end()) - cells.begin() < 16) continue;
      box /= kSub * kSub;
      ASSERT_TRUE(groundHit(camera.rayDirection(x + 0.5, y + 0.5), g));
      const double point = albedoAt(g, nullptr);  // the unfiltered look-up of before
      const double gpu = 0.5 * double(a.frame.rgba[i + 1]) / double(b.frame.rgba[i + 1]);
      gpuErr = std::max(gpuErr, std::abs(gpu - box));
      gpuSq += (gpu - box) * (gpu - box);
      pointErr = std::max(pointErr, std::abs(point - box));
      pointSq += (point - box) * (point - box);
      ++tested;
    }
  }
  const double gpuRms = std::sqrt(gpuSq / std::max(tested, 1)), pointRms = std::sqrt(pointSq / std::max(tested, 1));
  std::printf("[ globe    ] %d minified ground pixels: filtered vs box filter rms %.4f max %.4f; "
              "one tap at the centre rms %.4f max %.4f\n",
              tested, gpuRms, gpuErr, pointRms, pointErr);
  ASSERT_GE(tested, 500) << "the view must show far ground";
  // The scene aliases without a filter (the checker's contrast is 0.8) ...
  EXPECT_GT(pointRms, 0.25);
  // ... and the GPU's filter lands on the box filter's value: mipmaps of a checker of 2-texel
  // cells are 0.5 from level 2 on, the box filter of ≥ 16 cells is 0.5 ± its sampling noise and
  // the cells cut by the pixel's edges (0.4 / √(256) = 0.025 for independent rays).
  EXPECT_LT(gpuRms, 0.05);
  EXPECT_LT(gpuErr, 0.15);
}

}  // namespace
}  // namespace nph::test
