// Globe view (render/raycast/globe.h): the lon/lat -> world table against PROJ, and empty-space
// skipping under the curved mapping changes nothing (its jumps are conservative).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>

#include <OpenImageIO/imageio.h>

#include "../scene/gdal_raster_writer.h"
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
  scene::LonLat centre;  ///< the storm's centre
  GlobeScene() {
    centre = stormCentreLonLat(datagen::writeWrfHurricane(smallStormSpec(), data), smallStormSpec());
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

// How the GPU filtered the checker basemap, pixel by pixel, against a CPU box filter over the
// pixel's area: 16 × 16 rays through the pixel, each meeting the ground (`groundLonLat`: nullopt
// where a ray misses the ground or the imagery), the checker's albedo at each ray's lon/lat
// (`albedoAt`, which also names the checker cell). A pixel counts when it shows ground in both
// renders (no cloud), all its rays hit and they land in ≥ 16 distinct checker cells (there one tap
// at the centre is a coin toss).
struct FootprintFilterStats {
  int tested = 0;
  double gpuRms = 0.0, gpuMax = 0.0, pointRms = 0.0, pointMax = 0.0;
};
using AlbedoAt = std::function<double(const scene::LonLat&, long* cell)>;
FootprintFilterStats compareWithBoxFilter(
    const scene::Camera& camera, const render::RenderOutput& checker, const render::RenderOutput& uniform,
    const AlbedoAt& albedoAt, const std::function<std::optional<scene::LonLat>(const glm::dvec3&)>& groundLonLat) {
  constexpr int kSub = 16;
  FootprintFilterStats r;
  double gpuSq = 0.0, pointSq = 0.0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const std::size_t i = (std::size_t(y) * std::size_t(camera.width) + std::size_t(x)) * 4;
      if (checker.cloud_layer.rgba[i + 3] > 0.0f || uniform.cloud_layer.rgba[i + 3] > 0.0f ||
          uniform.frame.rgba[i + 1] < 1e-3f) {
        continue;
      }
      double box = 0.0;
      std::vector<long> cells;
      bool allHit = true;
      for (int sy = 0; sy < kSub && allHit; ++sy) {
        for (int sx = 0; sx < kSub && allHit; ++sx) {
          const auto ll = groundLonLat(camera.rayDirection(x + (sx + 0.5) / kSub, y + (sy + 0.5) / kSub));
          allHit = ll.has_value();
          long cell = 0;
          if (allHit) box += albedoAt(*ll, &cell);
          cells.push_back(cell);
        }
      }
      std::sort(cells.begin(), cells.end());
      if (!allHit || std::unique(cells.begin(), cells.end()) - cells.begin() < 16) continue;
      box /= kSub * kSub;
      const auto centre = groundLonLat(camera.rayDirection(x + 0.5, y + 0.5));
      if (!centre) continue;
      const double point = albedoAt(*centre, nullptr);  // the unfiltered look-up
      const double gpu = 0.5 * double(checker.frame.rgba[i + 1]) / double(uniform.frame.rgba[i + 1]);
      r.gpuMax = std::max(r.gpuMax, std::abs(gpu - box));
      gpuSq += (gpu - box) * (gpu - box);
      r.pointMax = std::max(r.pointMax, std::abs(point - box));
      pointSq += (point - box) * (point - box);
      ++r.tested;
    }
  }
  r.gpuRms = std::sqrt(gpuSq / std::max(r.tested, 1));
  r.pointRms = std::sqrt(pointSq / std::max(r.tested, 1));
  return r;
}

// The verdict of both views: ≥ 500 pixels tested; the scene aliases without a filter (the
// checker's contrast is 0.8) ... and the GPU's filter lands on the box filter's value: mipmaps of a
// checker of 2-texel cells are 0.5 from level 2 on, the box filter of ≥ 16 cells is 0.5 ± its
// sampling noise and the cells cut by the pixel's edges (0.4 / √(256) = 0.025 for independent rays).
void expectFilteredLikeTheBoxFilter(const char* view, const FootprintFilterStats& st) {
  std::printf("[ %-8s ] %d minified ground pixels: filtered vs box filter rms %.4f max %.4f; "
              "one tap at the centre rms %.4f max %.4f\n",
              view, st.tested, st.gpuRms, st.gpuMax, st.pointRms, st.pointMax);
  ASSERT_GE(st.tested, 500) << "the view must show far ground";
  EXPECT_GT(st.pointRms, 0.25);
  EXPECT_LT(st.gpuRms, 0.05);
  EXPECT_LT(st.gpuMax, 0.15);
}

// The checker and the uniform basemap rendered in one view with nothing added in front of the ground
// (no atmosphere, no cloud shadows): the ground pixel = albedo × light.
struct CheckerRenders {
  render::RenderOutput checker, uniform;
  std::unique_ptr<engine::Session> session;  ///< the checker's: its camera, georeference, rectangles
  const scene::Camera& camera() const { return session->prepared().camera; }
};
CheckerRenders renderCheckers(const std::string& view, const std::string& camera_json, const std::string& checker,
                              const std::string& uniform, int basemap_pixels = 256, double margin = 0.4) {
  auto scene = [&](const std::string& basemap) {
    return R"({"data": {"path": "x"}, "camera": )" + camera_json + R"(,
      "sun": {"azimuth_deg": 100, "elevation_deg": 60},
      "basemap": {"path": ")" +
           basemap + R"(", "margin": )" + std::to_string(margin) + R"(, "pixels_long_side": )" +
           std::to_string(basemap_pixels) + R"(},
      "quality": {"preset": "broadcast", "overrides": {"shadows": false}},
      "output": {"width": 160, "height": 90}, "height_exaggeration": 8, "view": ")" +
           view + R"("})";
  };
  CheckerRenders r;
  auto render = [&](const std::string& basemap, std::unique_ptr<engine::Session>* keep) {
    auto s = openSession(scene(basemap), globeScene().data);
    lighting::StyleSettings style = s->style();
    style.atmosphere = false;  // the ground's albedo times the light, nothing added in front
    s->setStyle(style);
    render::RenderOutput out = s->render(s->prepared().camera);
    if (keep) *keep = std::move(s);
    return out;
  };
  r.checker = render(checker, &r.session);
  r.uniform = render(uniform, nullptr);
  return r;
}

TEST_F(GlobeTest, ImageryIsFilteredOverThePixelFootprint) {
  ScratchDir dir("globe-imagery");
  const std::string checker = dir.file("checker.exr"), uniform = dir.file("uniform.exr");
  writeCheckerBasemap(checker, false);
  writeCheckerBasemap(uniform, true);
  const CheckerRenders r =
      renderCheckers("globe", R"({"preset": "oblique", "fov_deg": 40, "distance_scale": 24})", checker, uniform);
  const scene::EquirectangularImage lookup = scene::EquirectangularImage::load(checker);
  ASSERT_EQ(lookup.image().width, 2048) << "the checker must reach the globe at its own size";

  const double R = volume::kEarthRadius_m;
  const glm::dvec3 o = r.camera().position_m;
  auto groundLonLat = [&](const glm::dvec3& d) -> std::optional<scene::LonLat> {
    const double bq = glm::dot(o, d), c = glm::dot(o, o) - R * R, disc = bq * bq - c;
    if (disc < 0.0 || -bq - std::sqrt(disc) < 0.0) return std::nullopt;
    const glm::dvec3 g = o + (-bq - std::sqrt(disc)) * d;
    return scene::LonLat{glm::degrees(std::atan2(g.y, g.x)), glm::degrees(std::asin(g.z / glm::length(g)))};
  };
  auto albedoAt = [&](const scene::LonLat& ll, long* cell) {
    if (cell) {  // the 2-texel cells of the 2048 × 1024 texture
      const glm::dvec2 uv = scene::equirectUv(ll.lon_deg, ll.lat_deg);
      *cell = long(std::floor(uv.x * 1024.0)) * 4096 + long(std::floor(uv.y * 512.0));
    }
    return double(lookup.sampleLonLat(ll.lon_deg, ll.lat_deg).g);
  };
  const FootprintFilterStats st = compareWithBoxFilter(r.camera(), r.checker, r.uniform, albedoAt, groundLonLat);
  expectFilteredLikeTheBoxFilter("globe", st);
}

// The same for the flat view (issue 14 item 3): a low oblique look along the near basemap's cloud-free
// southern margin (margin 2: the rectangle reaches 800 km beyond the data), where each pixel's
// footprint on the plane z = 0 is long and thin. The whole-Earth checker's 39 km cells are too
// coarse here, so the checker is a regional GeoTIFF in lon/lat (EPSG:4326, written through GDAL)
// of cells of 1/32° (≈ 3.3 km) around the storm, which GDAL warps into the scene's map frame at
// 2048 pixels (≈ 0.8 km: ~4 per cell). The box filter evaluates the checker analytically at each
// ray's lon/lat (the scene's georeference).
void writeRegionalChecker(const std::string& path, scene::LonLat centre, bool uniform) {
  constexpr int kN = 2048;
  constexpr double kCellDeg = 1.0 / 64.0, kHalfDeg = 16.0;  // 2048 texels of 1/64°, cells of 2 texels
  std::vector<double> rgb(std::size_t(kN) * kN * 3);
  const double lon0 = std::floor(centre.lon_deg) - kHalfDeg, lat1 = std::floor(centre.lat_deg) + kHalfDeg;
  for (int y = 0; y < kN; ++y) {
    for (int x = 0; x < kN; ++x) {
      const double a = uniform ? 0.5 : (((x / 2 + y / 2) % 2) != 0 ? 0.9 : 0.1);
      for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * kN + std::size_t(x)) * 3 + std::size_t(c)] = a;
    }
  }
  scene::test::RasterSpec spec;
  spec.width = spec.height = kN;
  spec.geotransform = std::array<double, 6>{lon0, kCellDeg, 0.0, lat1, 0.0, -kCellDeg};
  spec.srs = "EPSG:4326";
  scene::test::writeGeoTiff(path, spec, rgb);
}

TEST_F(GlobeTest, FlatViewImageryIsFilteredOverThePixelFootprint) {
  ScratchDir dir("flat-imagery");
  const std::string checker = dir.file("checker.tif"), uniform = dir.file("uniform.tif");
  const scene::LonLat centre = globeScene().centre;
  writeRegionalChecker(checker, centre, false);
  writeRegionalChecker(uniform, centre, true);
  const CheckerRenders r = renderCheckers(
      "flat", R"({"position_m": [-700000, -500000, 50000], "target_m": [900000, -450000, 0], "fov_deg": 40})", checker,
      uniform, 2048, 2.0);
  const scene::PreparedScene& p = r.session->prepared();
  ASSERT_TRUE(p.geo && p.basemap_rect);
  const glm::dvec3 o = r.camera().position_m;
  const double lon0 = std::floor(centre.lon_deg) - 16.0, lat1 = std::floor(centre.lat_deg) + 16.0;
  auto albedoAt = [&](const scene::LonLat& ll, long* cell) {
    const long cx = long(std::floor((ll.lon_deg - lon0) * 32.0)), cy = long(std::floor((lat1 - ll.lat_deg) * 32.0));
    if (cell) *cell = cx * 65536 + cy;
    return ((cx + cy) % 2) != 0 ? 0.9 : 0.1;
  };
  auto groundLonLat = [&](const glm::dvec3& d) -> std::optional<scene::LonLat> {
    if (d.z >= 0.0) return std::nullopt;
    const glm::dvec2 g = glm::dvec2(o) + (-o.z / d.z) * glm::dvec2(d);  // flatGroundDistance without terrain
    const scene::WorldRect& rect = *p.basemap_rect;                     // the near basemap only
    if (g.x < rect.min_m.x || g.y < rect.min_m.y || g.x > rect.max_m.x || g.y > rect.max_m.y) return std::nullopt;
    return p.geo->lonLatFromWorld(g);
  };
  const FootprintFilterStats st = compareWithBoxFilter(r.camera(), r.checker, r.uniform, albedoAt, groundLonLat);
  expectFilteredLikeTheBoxFilter("flat", st);
}

}  // namespace
}  // namespace nph::test
