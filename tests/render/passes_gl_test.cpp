// Compositing passes (issue 15 item 1, "Done means"): the depth of a slab at a known distance,
// the shadow matte against the deep light map's ground transmittance, the passes recombining to
// the beauty (in memory and from the written multi-layer OpenEXR).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dlm_scenes.h"
#include "reference/dlm_reference.h"
#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "render_scenes.h"
#include "scene/passes.h"
#include "scene/scene_file.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"
#include "support/scratch_dir.h"

namespace nph::test {
namespace {

using PassesTest = GlTest;

struct LookingDown {
  render::RenderOutput out;
  volume::VolumeFrame frame;
  scene::Camera camera;
  render::DeepLightMap::Readback dlm;
  lighting::LightSpace light_space;
  lighting::DlmSettings dlm_settings;
  render::DlmStats dlm_stats;
};

// A camera 50 km above the centre of `v` looking straight down, 41×41 pixels, 60° field of view
// (a 58 km footprint on the ground, wider than the 24 km slab: the margins see no cloud).
LookingDown renderLookingDown(const ExtinctionVolumes& v, const scene::Sun& sun, const render::RenderSettings& rs) {
  LookingDown r;
  r.frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, r.frame, "passes-test");
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});
  const glm::dvec3 c = 0.5 * (r.frame.min_m() + r.frame.max_m());
  r.camera.position_m = {c.x, c.y, 50000.0};
  r.camera.target_m = {c.x, c.y, 0.0};
  r.camera.up = {0.0, 1.0, 0.0};
  r.camera.vertical_fov_deg = 60.0;
  r.camera.width = 41;
  r.camera.height = 41;
  render::CloudRenderer renderer;
  renderer.setPasses(true);
  r.out = renderer.render(tex, dlm, r.camera, sun, rs);
  r.dlm = dlm.readBack();
  r.light_space = dlm.lightSpace();
  r.dlm_settings = dlm.settings();
  r.dlm_stats = dlm.stats();
  return r;
}

// Where pixel (x, y)'s ray meets the ground plane z = 0.
glm::dvec3 groundPoint(const scene::Camera& cam, int x, int y) {
  const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
  return cam.position_m + (-cam.position_m.z / d.z) * d;
}

bool insideSlab(const volume::VolumeFrame& f, const glm::dvec3& g, double margin_m) {
  return g.x > f.min_m().x + margin_m && g.x < f.max_m().x - margin_m && g.y > f.min_m().y + margin_m &&
         g.y < f.max_m().y - margin_m;
}

// An optically thick slab seen from straight above: its Z is the transmittance-weighted depth of
// its top, known in closed form. The zero-padded trilinear profile ramps β linearly from 0 at
// h0 = top + dz/2 to β_max at the top voxel centre, so below h0 the optical depth is
// τ(s) = β_max·s²/(2·dz) and the depth of the light's origin past h0 is Rayleigh distributed with
// σ² = dz/β_max: mean σ·√(π/2). Z is planar (along the view axis): the same on every pixel over
// the flat top, although the rays off the centre are longer by 1/cos. Tolerance ½ step (the
// issue's bound: the march's opacity is taken once per step).
TEST_F(PassesTest, DepthOfAThickSlabIsItsTopAtAKnownDistance) {
  const double betaMax = 0.2;  // per metre: σ = 35 m, opaque 110 m below h0
  const ExtinctionVolumes v = homogeneousSlab(8, 8, 8, float(betaMax));
  render::RenderSettings rs;
  rs.jitter = false;
  rs.step_voxels = 0.1;  // 25 m steps
  rs.atmosphere = false;
  const auto r = renderLookingDown(v, scene::Sun{0.0, 60.0}, rs);
  ASSERT_TRUE(r.out.passes);
  const double dz = r.frame.voxel_size_m.z;
  const double step = rs.step_voxels * std::min({r.frame.voxel_size_m.x, r.frame.voxel_size_m.y, dz});
  const double h0 = r.frame.max_m().z + 0.5 * dz;
  const double expected = r.camera.position_m.z - h0 + std::sqrt(dz / betaMax) * std::sqrt(std::numbers::pi / 2.0);
  int over = 0, clear = 0;
  double rayLengthSpread = 0.0;
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      const std::size_t i = std::size_t(y) * 41 + std::size_t(x);
      const glm::dvec3 g = groundPoint(r.camera, x, y);
      const double alpha = r.out.cloud_layer.rgba[4 * i + 3];
      const double z = r.out.passes->depth_m[i];
      if (insideSlab(r.frame, g, 3000.0)) {
        ++over;
        ASSERT_GT(alpha, 0.99);
        EXPECT_NEAR(z, expected, 0.5 * step) << "pixel " << x << ", " << y;
        rayLengthSpread = std::max(rayLengthSpread, expected / -r.camera.rayDirection(x + 0.5, y + 0.5).z - expected);
      } else if (!insideSlab(r.frame, g, -3000.0)) {
        ++clear;
        EXPECT_EQ(alpha, 0.0);
        EXPECT_EQ(z, scene::kNoCloudDepth_m);
      }
    }
  }
  EXPECT_GT(over, 60);
  EXPECT_GT(clear, 400);
  EXPECT_GT(rayLengthSpread, 10.0 * step);  // a ray distance instead of planar Z would fail
}

// The shadow matte is the deep light map's light at the ground point the pixel sees: compared with
// the CPU twin of the GPU look-up on the read-back map (float against double: 1e-5), and with the
// CPU reference of the map's model (reference/dlm_reference.h, refine 1: the GPU build's exact
// arithmetic before compression, so within the compression bound ε plus rounding). Under the
// slab it lies between the direct transmittance exp(−τ/sin e) of a sun at elevation e through
// the slab's vertical optical depth τ and 1 (the map carries the forward-scattered light too),
// and it is 1 (within 2 %: the map's cone of forward scattering softens the shadow's edge over a
// few km) where the sun reaches the ground past the slab.
// Issue 19, twenty-third session: render()'s read-back paths (render::ReadBack) give the same
// images. Through the pixel-pack buffer (a GPU's default), straight into vectors (llvmpipe's) and
// by the driver's choice (Auto): the frame, the cloud layer and all four passes bit for bit.
// Without the cloud layer: the layer empty, the frame and the passes unchanged.
TEST_F(PassesTest, ReadBackPathsGiveTheSameImages) {
  const ExtinctionVolumes v = homogeneousSlab(8, 8, 8, 2e-3f);
  const volume::VolumeFrame frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "passes-test");
  const scene::Sun sun{30.0, 40.0};
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});
  scene::Camera camera;
  const glm::dvec3 c = 0.5 * (frame.min_m() + frame.max_m());
  camera.position_m = {c.x - 30000.0, c.y - 20000.0, 12000.0};  // oblique: sky, ground and cloud in view
  camera.target_m = {c.x, c.y, 1000.0};
  camera.up = {0.0, 0.0, 1.0};
  camera.vertical_fov_deg = 60.0;
  camera.width = 48;
  camera.height = 27;
  render::CloudRenderer renderer;
  renderer.setPasses(true);
  const render::RenderSettings rs;
  using Path = render::ReadBack::Path;
  const auto direct = renderer.render(tex, dlm, camera, sun, rs, {true, Path::Direct});
  const std::size_t bytesBefore = renderer.textureBytes();
  const auto pbo = renderer.render(tex, dlm, camera, sun, rs, {true, Path::PixelBuffer});
  const auto frameOnly = renderer.render(tex, dlm, camera, sun, rs, {false, Path::PixelBuffer});
  const auto automatic = renderer.render(tex, dlm, camera, sun, rs, {true, Path::Auto});
  ASSERT_TRUE(direct.passes && pbo.passes && frameOnly.passes && automatic.passes);
  const std::size_t n = std::size_t(camera.width) * std::size_t(camera.height);
  ASSERT_EQ(direct.frame.rgba.size(), 4 * n);
  ASSERT_EQ(direct.cloud_layer.rgba.size(), 4 * n);
  // The pack buffer (four RGBA32F images) is counted in the renderer's memory.
  EXPECT_EQ(renderer.textureBytes(), bytesBefore + 4 * 4 * n * sizeof(float));
  // The scene must exercise the images: cloud in the layer, sky and ground in the passes.
  EXPECT_GT(*std::max_element(direct.cloud_layer.rgba.begin(), direct.cloud_layer.rgba.end()), 0.05f);
  EXPECT_GT(*std::max_element(direct.passes->sky_rgb.begin(), direct.passes->sky_rgb.end()), 0.0f);
  EXPECT_GT(*std::max_element(direct.passes->ground_rgb.begin(), direct.passes->ground_rgb.end()), 0.0f);
  for (const render::RenderOutput* o : {&pbo, &frameOnly, &automatic}) {
    EXPECT_EQ(o->frame.rgba, direct.frame.rgba);
    EXPECT_EQ(o->passes->ground_rgb, direct.passes->ground_rgb);
    EXPECT_EQ(o->passes->sky_rgb, direct.passes->sky_rgb);
    EXPECT_EQ(o->passes->shadow, direct.passes->shadow);
    EXPECT_EQ(o->passes->depth_m, direct.passes->depth_m);
  }
  EXPECT_EQ(pbo.cloud_layer.rgba, direct.cloud_layer.rgba);
  EXPECT_EQ(automatic.cloud_layer.rgba, direct.cloud_layer.rgba);
  EXPECT_TRUE(frameOnly.cloud_layer.rgba.empty());
  EXPECT_EQ(frameOnly.cloud_layer.width, 0);
}

TEST_F(PassesTest, ShadowMatteIsTheDeepLightMapGroundTransmittance) {
  const double beta = 5e-4;  // 2 km slab: τ = 1
  const ExtinctionVolumes v = homogeneousSlab(8, 8, 8, float(beta));
  render::RenderSettings rs;
  rs.jitter = false;
  const scene::Sun sun{30.0, 60.0};
  const auto r = renderLookingDown(v, sun, rs);
  ASSERT_TRUE(r.out.passes);
  lighting::LightSpace lsf = r.light_space;  // the GPU's float geometry, as dlm_reference_gl_test
  for (glm::dvec3* vec : {&lsf.u, &lsf.v, &lsf.w, &lsf.origin_m}) *vec = glm::dvec3(glm::vec3(*vec));
  const reference::DlmReference ref(v, r.frame, lsf, r.dlm_settings, double(float(r.dlm_stats.step_m)),
                                    r.dlm_stats.steps, 1);
  const double direct = std::exp(-beta * 2000.0 / std::sin(glm::radians(60.0)));
  double maxTwin = 0.0, maxRef = 0.0;
  int shadowed = 0, lit = 0;
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      const std::size_t i = std::size_t(y) * 41 + std::size_t(x);
      const glm::dvec3 g = groundPoint(r.camera, x, y);
      const double matte = r.out.passes->shadow[i];
      maxTwin = std::max(maxTwin, std::abs(matte - render::DeepLightMap::lookup(r.dlm, r.light_space, g)));
      maxRef = std::max(maxRef, std::abs(matte - ref.intensityAt(g)));
      // The sun ray from g leaves the slab's top 2000/tan(60°) = 1155 m towards the sun.
      if (insideSlab(r.frame, g, 4000.0)) {
        ++shadowed;
        EXPECT_GT(matte, direct) << "pixel " << x << ", " << y;
        EXPECT_LT(matte, 0.9) << "pixel " << x << ", " << y;
      } else if (!insideSlab(r.frame, g, -4000.0)) {
        ++lit;
        EXPECT_NEAR(matte, 1.0, 0.02) << "pixel " << x << ", " << y;  // the cone of forward scattering blurs the edge
      }
    }
  }
  EXPECT_LE(maxTwin, 1e-5);
  EXPECT_LE(maxRef, r.dlm_settings.epsilon + 1e-3);
  EXPECT_GT(shadowed, 30);
  EXPECT_GT(lit, 200);
}

// beauty = cloud + (1 − cloud.α)·(ground + sky) for the small storm in the flat oblique view and
// on the globe, the atmosphere on and off: exactly in memory (the same floats; 1e-6 for the sum's
// rounding), and within 1e-3 relative from the written multi-layer OpenEXR (half floats: 2^-11).
class PassesRecombine : public GlTest, public ::testing::WithParamInterface<std::tuple<std::string, bool>> {};

TEST_P(PassesRecombine, IntoTheBeautyInMemoryAndFromTheExr) {
  const auto [view, atmosphere] = GetParam();
  ScratchDir dir("passes");
  const std::string data = dir.file("storm.nc");
  datagen::writeWrfHurricane(smallStormSpec(), data);
  auto session = openSession(R"({"data": {"path": "x"}, "view": ")" + view + R"(",
      "camera": {"preset": "overview", "fov_deg": 40, "distance_scale": )" +
                                 (view == "globe" ? "3" : "1") + R"(},
      "sun": {"azimuth_deg": 100, "elevation_deg": 25}, "height_exaggeration": 8,
      "output": {"width": 96, "height": 54, "passes": true}})",
                             data);
  lighting::StyleSettings style = session->style();
  style.atmosphere = atmosphere;
  session->setStyle(style);
  const auto out = session->render(session->prepared().camera);
  ASSERT_TRUE(out.passes);
  const scene::FramePasses& p = *out.passes;
  const std::size_t n = std::size_t(p.width) * std::size_t(p.height);
  double maxErr = 0.0, sumAlpha = 0.0, sumSky = 0.0, sumGround = 0.0, minShadow = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float a = out.cloud_layer.rgba[4 * i + 3];
    sumAlpha += double(a);
    minShadow = std::min(minShadow, double(p.shadow[i]));
    for (std::size_t c = 0; c < 3; ++c) {
      const float rebuilt =
          out.cloud_layer.rgba[4 * i + c] + (1.0f - a) * (p.ground_rgb[3 * i + c] + p.sky_rgb[3 * i + c]);
      maxErr = std::max(maxErr, double(std::abs(rebuilt - out.frame.rgba[4 * i + c])));
      sumSky += double(p.sky_rgb[3 * i + c]);
      sumGround += double(p.ground_rgb[3 * i + c]);
    }
  }
  EXPECT_LE(maxErr, 1e-6);
  // Each pass carries something: a test on empty passes could not fail.
  EXPECT_GT(sumAlpha, 0.01 * double(n));
  EXPECT_GT(sumGround, 0.0);
  EXPECT_LT(minShadow, 0.5);  // the storm shadows the ground somewhere in view
  if (atmosphere) {
    EXPECT_GT(sumSky, 0.0);
  }

  // Written and read back: channel names as a compositor sees them, and the recombination.
  const std::string exr = dir.file("passes.exr");
  scene::OutputSpec spec = session->scene().output;
  spec.passes = true;
  scene::writeImage(scene::outputFrame(spec, out.frame, out.cloud_layer, &p), exr, spec.image);
  auto in = OIIO::ImageInput::open(exr);
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& s = in->spec();
  const std::vector<std::string> expectedNames{"R",       "G",       "B",       "A",        "Z",        "cloud.R",
                                               "cloud.G", "cloud.B", "cloud.A", "ground.R", "ground.G", "ground.B",
                                               "sky.R",   "sky.G",   "sky.B",   "shadow.Y"};
  // OpenEXR stores channels sorted by name; OIIO reads them back in its own order: compare as sets.
  std::vector<std::string> names(s.channelnames.begin(), s.channelnames.end());
  std::vector<std::string> want = expectedNames;
  std::sort(names.begin(), names.end());
  std::sort(want.begin(), want.end());
  ASSERT_EQ(names, want);
  std::vector<float> px(n * std::size_t(s.nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  auto channel = [&](const std::string& name) {
    const auto it = std::find(s.channelnames.begin(), s.channelnames.end(), name);
    return std::size_t(it - s.channelnames.begin());
  };
  const std::size_t nc = std::size_t(s.nchannels);
  const std::size_t ca = channel("cloud.A");
  double maxRel = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* q = &px[i * nc];
    auto at = [&](const std::string& name) { return double(q[channel(name)]); };
    for (const char* c : {"R", "G", "B"}) {
      const std::string ch(c);
      const double rebuilt = at("cloud." + ch) + (1.0 - double(q[ca])) * (at("ground." + ch) + at("sky." + ch));
      const double beauty = at(ch);
      maxRel = std::max(maxRel, std::abs(rebuilt - beauty) / std::max(beauty, 1e-3));
    }
    EXPECT_EQ(q[channel("Z")], p.depth_m[i]);  // Z is stored as float
  }
  EXPECT_LE(maxRel, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Views, PassesRecombine,
                         ::testing::Combine(::testing::Values("flat", "globe"), ::testing::Bool()));

}  // namespace
}  // namespace nph::test
