// Globe view (render/raycast/globe.h): the lon/lat -> world table against PROJ, and empty-space
// skipping under the curved mapping changes nothing (its jumps are conservative).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "render/raycast/globe.h"
#include "render_scenes.h"
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

}  // namespace
}  // namespace nph::test
