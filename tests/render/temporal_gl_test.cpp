// Temporal accumulation for the interactive path (RenderSettings::temporal_history; issue 19 item 4;
// render/raycast/temporal_accumulation.h, glsl/render/temporal.comp): each frame takes the next
// sample of the jitter and sub-pixel sequence and folds it into a history reprojected through the
// scene's depth. A still view must become exactly the mean samples_per_pixel gives; a moving view
// must come closer to the converged picture than one sample does, without trails; anything but the
// camera that changes starts afresh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"
#include "support/image_compare.h"
#include "volume/volume_frame.h"

namespace nph::test {
namespace {

using TemporalTest = GlTest;

// Cumulus-like puffs (Gaussian blobs of water, an icy one above) over a 40 × 40 km grid: soft
// edges, opaque cores, a shadowed ground — everything the jitter makes noisy and a camera move
// reveals or hides.
ExtinctionVolumes puffs() {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(40, 40, 16, 1000.0, 500.0, 500.0);
  struct Puff {
    double x, y, z, r;
    bool ice;
  };
  const Puff list[] = {{12, 14, 4, 5, false}, {26, 22, 5, 6, false}, {18, 30, 3, 4, false}, {30, 10, 12, 7, true}};
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i)
        for (const Puff& p : list) {
          const double d2 = ((i - p.x) * (i - p.x) + (j - p.y) * (j - p.y)) / (p.r * p.r) +
                            (k - p.z) * (k - p.z) / (0.4 * p.r * 0.4 * p.r * 4.0);
          const float beta = float(0.01 * std::exp(-2.0 * d2));
          float& cell = (p.ice ? v.ice_per_m : v.water_per_m)[v.index(i, j, k)];
          cell = std::max(cell, beta > 1e-5f ? beta : 0.0f);
        }
  v.updateMaxima();
  return v;
}

struct Scene {
  ExtinctionVolumes v = puffs();
  volume::VolumeFrame frame = volume::frameOf(v, 2.0);
  render::VolumeTextures tex = render::VolumeTextures::upload(v, frame, "temporal-puffs");
  scene::Sun sun{150.0, 35.0};
  render::DeepLightMap dlm;
  Scene() { dlm.build(tex, -sun.toSun(), lighting::DlmSettings{}); }

  // The camera 60 km from the grid's centre at `azimuth_deg`, 25° above it.
  scene::Camera camera(double azimuth_deg) const {
    const glm::dvec3 c = 0.5 * (frame.min_m() + frame.max_m());
    const double a = glm::radians(azimuth_deg), e = glm::radians(25.0), d = 60000.0;
    scene::Camera cam;
    cam.position_m = {c.x + d * std::cos(e) * std::sin(a), c.y + d * std::cos(e) * std::cos(a), c.z + d * std::sin(e)};
    cam.target_m = {c.x, c.y, 2000.0};
    cam.up = {0.0, 0.0, 1.0};
    cam.vertical_fov_deg = 40.0;
    cam.width = 96;
    cam.height = 54;
    return cam;
  }
};

// RMS difference of the frames' RGB, relative to the reference's RMS value.
double relativeRms(const scene::RgbaImage& a, const scene::RgbaImage& ref) {
  double d2 = 0.0, r2 = 0.0;
  for (std::size_t i = 0; i < ref.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = double(a.rgba[i]) - double(ref.rgba[i]), r = double(ref.rgba[i]);
    d2 += d * d;
    r2 += r * r;
  }
  return std::sqrt(d2 / r2);
}

// A still view: frame k of the accumulation is the running mean of samples 0 … k, the same
// arithmetic in the same order as samples_per_pixel = k + 1 in one render — the same floats up to
// the order of the operations' rounding (bound 1e-6 of the largest value). Past N frames the mean
// slides (an exponential average of weight 1/N): still close to the mean of N samples.
TEST_F(TemporalTest, StillViewIsTheMeanOfItsSamples) {
  Scene s;
  const scene::Camera cam = s.camera(200.0);
  render::CloudRenderer accumulating, reference;
  render::RenderSettings taa;
  taa.temporal_history = 8;
  render::RenderOutput out;
  for (int k = 0; k < 8; ++k) out = accumulating.render(s.tex, s.dlm, cam, s.sun, taa);
  EXPECT_EQ(accumulating.temporal().frames(), 8);
  render::RenderSettings spp;
  spp.samples_per_pixel = 8;
  const render::RenderOutput mean = reference.render(s.tex, s.dlm, cam, s.sun, spp);
  const render::RenderOutput one = reference.render(s.tex, s.dlm, cam, s.sun, {});
  const float peak = *std::max_element(mean.frame.rgba.begin(), mean.frame.rgba.end());
  double maxFrame = 0.0, maxLayer = 0.0;
  for (std::size_t i = 0; i < mean.frame.rgba.size(); ++i) {
    maxFrame = std::max(maxFrame, double(std::abs(out.frame.rgba[i] - mean.frame.rgba[i])));
    maxLayer = std::max(maxLayer, double(std::abs(out.cloud_layer.rgba[i] - mean.cloud_layer.rgba[i])));
  }
  EXPECT_LE(maxLayer, 1e-6 * double(peak));
  // The frame is recomposed from the two resolved layers, mean(C) + (1 − mean α)·mean(background),
  // where the samples' mean composite is mean(C + (1 − α)·background): they differ by the
  // covariance of α and the background over a pixel's samples, at edges only.
  EXPECT_LE(maxFrame, 1e-3 * double(peak));
  // The scene has noise to average: one sample differs from eight.
  EXPECT_GT(relativeRms(one.frame, mean.frame), 1e-3);
}

// A moving view, as `nephele view` draws it while the camera moves: the draft preset's march
// (step 1 voxel, clouds at ½ resolution upsampled), one sample per pixel and frame, the camera
// orbiting by 0.5° per frame (≈ 1 pixel at the image's centre) for 24 frames. Against the
// converged picture of the last camera (the same march, 64 samples per pixel: what the jitter and
// the sub-pixel positions average to; the march's own bias is not the accumulation's to remove),
// the accumulated frame must be closer than one sample — Muth 2026 §3.4.9's half-resolution
// march filled in by the frames (N = 4, the viewer's). A sudden turn by 40° is a cut: the history
// starts afresh and the frame after it is exactly the plain render's (an old view clamped into
// it was 9× one sample's error in this scene before the cut rule). The table of errors for N = 2 … 16
// (the noise-against-lag trade-off) is docs/rendering.md "Temporal accumulation".
TEST_F(TemporalTest, MovingViewComesCloserToTheConvergedPictureWithoutTrails) {
  Scene s;
  render::CloudRenderer converged;
  render::RenderSettings draft;
  draft.step_voxels = 1.0;
  draft.cloud_resolution = 2;
  render::RenderSettings many = draft;
  many.samples_per_pixel = 64;
  const double last = 200.0 + 0.5 * 23;
  const render::RenderOutput truth = converged.render(s.tex, s.dlm, s.camera(last), s.sun, many);
  render::CloudRenderer plain;
  const render::RenderOutput one = plain.render(s.tex, s.dlm, s.camera(last), s.sun, draft);
  const double single = relativeRms(one.frame, truth.frame);
  std::printf("temporal accumulation, draft march, orbit 0.5 deg/frame, 24 frames, 96 x 54:\n"
              "relative RMS error of the frame / the cloud layer against the same march's 64 spp\n");
  std::printf("  one sample:         %.4f / %.4f\n", single, relativeRms(one.cloud_layer, truth.cloud_layer));
  double atFour = 0.0;
  for (int n : {2, 4, 8, 16}) {
    render::CloudRenderer r;
    render::RenderSettings taa = draft;
    taa.temporal_history = n;
    render::RenderOutput out, still;
    for (int f = 0; f < 24; ++f) out = r.render(s.tex, s.dlm, s.camera(200.0 + 0.5 * f), s.sun, taa);
    render::CloudRenderer q;
    for (int f = 0; f < 24; ++f) still = q.render(s.tex, s.dlm, s.camera(last), s.sun, taa);
    const double e = relativeRms(out.frame, truth.frame);
    std::printf("  N = %2d: moving %.4f / %.4f (%.2fx one sample's), still %.4f / %.4f\n", n, e,
                relativeRms(out.cloud_layer, truth.cloud_layer), e / single, relativeRms(still.frame, truth.frame),
                relativeRms(still.cloud_layer, truth.cloud_layer));
    if (n == 4) {
      atFour = e;
      // Pictures for docs/rendering.md "Temporal accumulation" (the test's output directory).
      scene::writePng(out.frame, testOutputDir() + "/temporal-moving-n4.png");
      scene::writePng(one.frame, testOutputDir() + "/temporal-moving-one-sample.png");
      scene::writePng(truth.frame, testOutputDir() + "/temporal-moving-converged.png");
    }
  }
  EXPECT_LT(atFour, 0.85 * single);

  // The cut: 24 frames accumulated at one view, then 40° round the target.
  render::CloudRenderer r;
  render::RenderSettings taa = draft;
  taa.temporal_history = 8;
  for (int f = 0; f < 24; ++f) r.render(s.tex, s.dlm, s.camera(200.0), s.sun, taa);
  const render::RenderOutput jumped = r.render(s.tex, s.dlm, s.camera(240.0), s.sun, taa);
  EXPECT_EQ(r.temporal().frames(), 1);
  // A fresh history starts at sample 0: the frame a render without the accumulation gives.
  const render::RenderOutput plainJumped = plain.render(s.tex, s.dlm, s.camera(240.0), s.sun, draft);
  EXPECT_EQ(jumped.cloud_layer.rgba, plainJumped.cloud_layer.rgba);
  EXPECT_EQ(jumped.frame.rgba, plainJumped.frame.rgba);
}

// Anything but the camera that changes the picture starts afresh: a new sun (the key dispatch()
// compares), a reset by the caller, a new size.
TEST_F(TemporalTest, ChangesOtherThanTheCameraStartAfresh) {
  Scene s;
  render::CloudRenderer r;
  render::RenderSettings taa;
  taa.temporal_history = 8;
  for (int k = 0; k < 4; ++k) r.render(s.tex, s.dlm, s.camera(200.0), s.sun, taa);
  EXPECT_EQ(r.temporal().frames(), 4);
  const scene::Sun other{160.0, 35.0};
  r.render(s.tex, s.dlm, s.camera(200.0), other, taa);
  EXPECT_EQ(r.temporal().frames(), 1);
  r.render(s.tex, s.dlm, s.camera(200.0), other, taa);
  EXPECT_EQ(r.temporal().frames(), 2);
  r.resetTemporalHistory();
  r.render(s.tex, s.dlm, s.camera(200.0), other, taa);
  EXPECT_EQ(r.temporal().frames(), 1);
  scene::Camera wider = s.camera(200.0);
  wider.width = 80;
  r.render(s.tex, s.dlm, s.camera(200.0), other, taa);
  r.render(s.tex, s.dlm, wider, other, taa);
  EXPECT_EQ(r.temporal().frames(), 1);
  // Turned off: the histories and the eye pass's extra layers are released (the renderer's bytes
  // fall by 92 per pixel: 2 × (16 + 16 + 4) of history, 4 + 16 of the layers), and turned on again
  // the history starts afresh.
  const std::size_t on = r.textureBytes();
  EXPECT_GT(r.temporal().textureBytes(), 0u);
  r.render(s.tex, s.dlm, wider, other, {});
  EXPECT_EQ(r.temporal().textureBytes(), 0u);
  EXPECT_EQ(on - r.textureBytes(), std::size_t(92) * std::size_t(wider.width) * std::size_t(wider.height));
  r.render(s.tex, s.dlm, wider, other, taa);
  EXPECT_EQ(r.temporal().frames(), 1);
  EXPECT_EQ(r.textureBytes(), on);
  // Off: no history kept, the frame as before (bit for bit the first sample's).
  render::CloudRenderer plain;
  const auto a = plain.render(s.tex, s.dlm, s.camera(200.0), s.sun, {});
  const auto b = plain.render(s.tex, s.dlm, s.camera(200.0), s.sun, {});
  EXPECT_EQ(a.frame.rgba, b.frame.rgba);
  EXPECT_EQ(plain.temporal().textureBytes(), 0u);
}

}  // namespace
}  // namespace nph::test
