// Samples per pixel (RenderSettings::samples_per_pixel, the knob `samples_per_pixel`;
// glsl/render/clouds.comp runningMean): the eye pass at sub-pixel positions of the R2 sequence,
// averaged — a box filter over each pixel. Checked against the exact pixel coverage of a sharp
// cloud edge, computed from the camera's own rays.
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

using SamplesPerPixelTest = GlTest;

// Sample k of a pixel lies in [0, 1)², the first at the centre, and the first 64 cover the pixel
// evenly: every quarter of it holds 16 ± 3.
TEST(SubpixelPosition, CentreFirstThenEvenCoverage) {
  EXPECT_EQ(render::subpixelPosition(0), glm::vec2(0.5f, 0.5f));
  int quarter[2][2] = {{0, 0}, {0, 0}};
  for (int k = 0; k < 64; ++k) {
    const glm::vec2 s = render::subpixelPosition(k);
    ASSERT_GE(s.x, 0.0f);
    ASSERT_LT(s.x, 1.0f);
    ASSERT_GE(s.y, 0.0f);
    ASSERT_LT(s.y, 1.0f);
    ++quarter[s.x < 0.5f ? 0 : 1][s.y < 0.5f ? 0 : 1];
  }
  for (auto& row : quarter)
    for (int n : row) EXPECT_NEAR(n, 16, 3);
}

// A slab of opaque cloud (β = 0.5 /m over 1 km of height, columns 10 … 21 of a 1 km grid, every
// row) seen straight down from 1000 km through a camera rolled by 17°, so its two edges cross the
// 48 × 48 pixels at every fractional position. Trilinear filtering puts each edge at the centre of
// the last clear column (x = 9.5 and 22.5 km; β rises to τ = 1 within 2 m of it, < 0.01 pixel), and
// from 1000 km a ray drifts < 0.02 pixel across the slab's height, so a pixel's exact alpha is the
// fraction of its area whose ray meets the mid-height plane between the two edges — counted here
// on a 64 × 64 lattice of rays through the pixel. One sample per pixel can only give 0 or 1 there;
// 64 samples must give the coverage within the R2 points' discrepancy.
TEST_F(SamplesPerPixelTest, EdgePixelsTakeTheirCoverage) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(32, 32, 8, 1000.0, 250.0, 1000.0);
  for (int k = 2; k <= 5; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 10; i <= 21; ++i) v.water_per_m[v.index(i, j, k)] = 0.5f;
  v.updateMaxima();
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  auto tex = render::VolumeTextures::upload(v, frame, "slab", {.reconstruction = volume::Reconstruction::Trilinear});
  const scene::Sun sun{150.0, 60.0};
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});

  scene::Camera camera;
  camera.position_m = {16200.0, 16000.0, 1.0e6};
  camera.target_m = {16200.0, 16000.0, 0.0};
  const double roll = 17.0 * 3.14159265358979 / 180.0;
  camera.up = {std::sin(roll), std::cos(roll), 0.0};
  camera.width = camera.height = 48;
  camera.vertical_fov_deg = 2.0 * std::atan(12000.0 / 998000.0) * 180.0 / 3.14159265358979;  // 24 km
  camera.far_m = 1.0e7;

  // Exact coverage: the rays through a 64 × 64 lattice in the pixel, cut with z = 2000 m.
  const double xLo = 9500.0, xHi = 22500.0, zMid = 2000.0;
  std::vector<double> coverage(std::size_t(camera.width * camera.height));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      int inside = 0;
      for (int b = 0; b < 64; ++b)
        for (int a = 0; a < 64; ++a) {
          const glm::dvec3 d = camera.rayDirection(x + (a + 0.5) / 64.0, y + (b + 0.5) / 64.0);
          const glm::dvec3 p = camera.position_m + (zMid - camera.position_m.z) / d.z * d;
          inside += p.x > xLo && p.x < xHi ? 1 : 0;
        }
      coverage[std::size_t(y * camera.width + x)] = inside / 4096.0;
    }

  std::vector<bool> nearEdge(coverage.size(), false);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      for (int dy = -4; dy <= 4; ++dy)
        for (int dx = -4; dx <= 4; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= camera.width || yy >= camera.height) continue;
          const double c = coverage[std::size_t(yy * camera.width + xx)];
          if (c > 0.0 && c < 1.0) nearEdge[std::size_t(y * camera.width + x)] = true;
        }

  render::RenderSettings rs;
  rs.atmosphere = false;
  render::CloudRenderer renderer;
  struct Error {
    double max = 0.0, mean = 0.0;
    int edgePixels = 0;
  };
  auto errorAt = [&](int samples) {
    rs.samples_per_pixel = samples;
    const auto out = renderer.render(tex, dlm, camera, sun, rs);
    Error e;
    for (std::size_t i = 0; i < coverage.size(); ++i) {
      const double alpha = double(out.cloud_layer.rgba[4 * i + 3]);
      const double c = coverage[i];
      // Wholly clear or wholly cloud: every sample agrees. With reduced-resolution clouds the
      // pixels within the upsampling's reach of an edge (2 reduced = 4 full pixels) count as edge.
      const bool whole = c == 0.0 || c == 1.0;
      if (whole && (rs.cloud_resolution == 1 || !nearEdge[i])) {
        EXPECT_NEAR(alpha, c, 1e-3) << "pixel " << i << " with " << samples << " samples";
        continue;
      }
      e.max = std::max(e.max, std::abs(alpha - c));
      e.mean += std::abs(alpha - c);
      ++e.edgePixels;
    }
    e.mean /= std::max(e.edgePixels, 1);
    std::printf("[ spp      ] %2d samples, clouds at 1/%d: %d edge pixels, |alpha - coverage| max %.3f, mean %.4f\n",
                samples, rs.cloud_resolution, e.edgePixels, e.max, e.mean);
    return e;
  };
  const Error one = errorAt(1), sixteen = errorAt(16), many = errorAt(64);
  ASSERT_GT(one.edgePixels, 60) << "both edges must cross the image";
  EXPECT_GT(one.max, 0.3);  // one sample: 0 or 1 on a partly covered pixel
  EXPECT_LT(sixteen.mean, 0.5 * one.mean);
  EXPECT_LE(many.max, 0.08);
  EXPECT_LE(many.mean, 0.02);

  // `nephele view` refines a still frame one sample per dispatch (RenderSettings::first_sample):
  // four dispatches of one sample each leave the same floats as one dispatch of four.
  rs.samples_per_pixel = 4;
  const auto atOnce = renderer.render(tex, dlm, camera, sun, rs);
  rs.samples_per_pixel = 1;
  render::RenderOutput stepwise;
  for (int k = 0; k < 4; ++k) {
    rs.first_sample = k;
    stepwise = renderer.render(tex, dlm, camera, sun, rs);
  }
  EXPECT_EQ(stepwise.frame.rgba, atOnce.frame.rgba);
  EXPECT_EQ(stepwise.cloud_layer.rgba, atOnce.cloud_layer.rgba);

  // Reduced-resolution clouds (the knob cloud_resolution; glsl/render/clouds.comp upsampleClouds)
  // compose with both: the reduced march takes the samples at sub-pixel positions of its own
  // (larger) pixels, so they cover the full pixels under it, and the full-resolution pass folds
  // each upsampled sample into the means; the progressive refinement folds the same floats as one
  // dispatch. The edge is then the reduced pixel's box (2 pixels wide) followed by the bilinear
  // tent (half-width 2 pixels): its step response leaves a whole pixel next to the edge at 0.69
  // instead of 1 in the continuous limit (0.31 off); measured max 0.32, mean 0.042 over the pixels
  // within 4 of the edge: bounds 0.4 and 0.06.
  rs.cloud_resolution = 2;
  rs.first_sample = 0;
  const Error halfMany = errorAt(64);
  EXPECT_LE(halfMany.max, 0.4);
  EXPECT_LE(halfMany.mean, 0.06);
  rs.samples_per_pixel = 4;
  const auto halfAtOnce = renderer.render(tex, dlm, camera, sun, rs);
  rs.samples_per_pixel = 1;
  for (int k = 0; k < 4; ++k) {
    rs.first_sample = k;
    stepwise = renderer.render(tex, dlm, camera, sun, rs);
  }
  EXPECT_EQ(stepwise.frame.rgba, halfAtOnce.frame.rgba);
  EXPECT_EQ(stepwise.cloud_layer.rgba, halfAtOnce.cloud_layer.rgba);
}

}  // namespace
}  // namespace nph::test
