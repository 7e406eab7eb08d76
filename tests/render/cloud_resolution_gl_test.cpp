// Reduced-resolution clouds (RenderSettings::cloud_resolution, the knob `cloud_resolution`; issue 19
// item 4; glsl/render/clouds.comp upsampleClouds): the clouds marched at W/s × H/s and upsampled
// by a joint bilateral filter guided by where each full-resolution ray's march ends. Here: an
// opaque edge in front of cloud must keep its side. The golden scenes' 2-vs-1 bounds are in
// golden_gl_test.cpp (CloudResolutionTest), the composition with samples per pixel and the
// progressive refinement in samples_per_pixel_gl_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/camera.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"
#include "volume/volume_frame.h"

namespace nph::test {
namespace {

using CloudResolutionEdgeTest = GlTest;

// A deck of opaque cloud (β = 0.5 /m, 1 km thick, over the whole 32 × 32 km grid) seen straight
// down from 1000 km, and in front of it, halfway down, the host's opaque geometry (a HostDepth
// buffer, as the plugin API passes it) over the image's left part, bounded by a slanted edge
// (x < 21 + 0.4·y pixels) so that the edge crosses the reduced pixels at every phase. At full
// resolution α is 0 wherever the host's geometry stops the ray before the deck and 1 elsewhere.
// Reduced to ½ and ¼, the upsampling must give the same α on both sides up to the edge: a reduced
// ray that passed beside the geometry ends its march ~500 km farther than a full-resolution ray
// stopped by it, so the range kernel leaves it out (and vice versa), and no pixel takes the other
// side's value (bound 1e-3: the values are exactly 0 and 1 on both sides; the bound only allows
// for rounding in the filter's weights). The same upsampling blind to the guide
// (EyePassBaseline::depth_blind_upsampling) blends the two sides over a reduced pixel along the
// edge, which the test must see (> 0.2).
TEST_F(CloudResolutionEdgeTest, HostGeometryEdgeKeepsItsSide) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(32, 32, 8, 1000.0, 250.0, 1000.0);
  for (int k = 2; k <= 5; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) v.water_per_m[v.index(i, j, k)] = 0.5f;
  v.updateMaxima();
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  auto tex = render::VolumeTextures::upload(v, frame, "deck", {.reconstruction = volume::Reconstruction::Trilinear});
  const scene::Sun sun{150.0, 60.0};
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});

  scene::Camera camera;
  camera.position_m = {16000.0, 16000.0, 1.0e6};
  camera.target_m = {16000.0, 16000.0, 0.0};
  camera.up = {0.0, 1.0, 0.0};
  camera.width = 64;
  camera.height = 48;
  camera.vertical_fov_deg = 2.0 * std::atan(10000.0 / 998000.0) * 180.0 / 3.14159265358979;  // 20 km
  camera.far_m = 1.0e7;

  // The host's depth buffer: window depth of the view-space plane z = −500 km on the left of the
  // edge, 1 (nothing) on the right; GL rows (row 0 at the bottom).
  const glm::dvec4 clip = camera.clipFromView() * glm::dvec4(0.0, 0.0, -5.0e5, 1.0);
  const float nearDepth = float(0.5 * clip.z / clip.w + 0.5);
  const auto hostSide = [](int x, int y) { return x + 0.5 < 21.0 + 0.4 * (y + 0.5); };
  std::vector<float> depth(std::size_t(camera.width * camera.height));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      depth[std::size_t((camera.height - 1 - y) * camera.width + x)] = hostSide(x, y) ? nearDepth : 1.0f;
  gl::Texture host = gl::Texture::create2D(GL_R32F, camera.width, camera.height).label("host depth");
  glTextureSubImage2D(host.id(), 0, 0, 0, camera.width, camera.height, GL_RED, GL_FLOAT, depth.data());

  render::RenderSettings rs;
  rs.atmosphere = false;
  const render::ViewRays view = render::ViewRays::fromCamera(camera);
  const auto alphaAt = [&](render::CloudRenderer& renderer, int divisor) {
    rs.cloud_resolution = divisor;
    renderer.dispatch(tex, dlm, view, sun, rs, {host.id()});
    std::vector<float> rgba(std::size_t(4 * camera.width * camera.height));
    glGetTextureImage(renderer.cloudLayer().id(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)),
                      rgba.data());
    std::vector<float> alpha(rgba.size() / 4);
    for (std::size_t i = 0; i < alpha.size(); ++i) alpha[i] = rgba[4 * i + 3];
    return alpha;
  };
  render::CloudRenderer renderer, blindRenderer;
  blindRenderer.setBaseline({.depth_blind_upsampling = true});
  const std::vector<float> full = alphaAt(renderer, 1), half = alphaAt(renderer, 2), quarter = alphaAt(renderer, 4),
                           blind = alphaAt(blindRenderer, 2);

  int hostPixels = 0;
  double maxHalf = 0.0, maxQuarter = 0.0, maxBlind = 0.0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const std::size_t i = std::size_t(y * camera.width + x);
      const bool hidden = hostSide(x, y);
      hostPixels += hidden ? 1 : 0;
      ASSERT_NEAR(full[i], hidden ? 0.0 : 1.0, 1e-3) << "full resolution, pixel " << x << ", " << y;
      maxHalf = std::max(maxHalf, std::abs(double(half[i]) - double(full[i])));
      maxQuarter = std::max(maxQuarter, std::abs(double(quarter[i]) - double(full[i])));
      maxBlind = std::max(maxBlind, std::abs(double(blind[i]) - double(full[i])));
    }
  std::printf("[ cloud res] host edge, %d of %d pixels behind the host's geometry: max |alpha - full| 1/2 %.2e, "
              "1/4 %.2e, 1/2 blind to depth %.3f\n",
              hostPixels, camera.width * camera.height, maxHalf, maxQuarter, maxBlind);
  ASSERT_GT(hostPixels, camera.width * camera.height / 4);
  EXPECT_LE(maxHalf, 1e-3);
  EXPECT_LE(maxQuarter, 1e-3);
  EXPECT_GT(maxBlind, 0.2) << "without the guide the two sides must blend along the edge";
}

}  // namespace
}  // namespace nph::test
