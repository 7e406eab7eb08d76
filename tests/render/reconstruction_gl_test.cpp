// The cubic B-spline reconstruction (issue 13; volume/reconstruction.h, glsl/dlm/volume.glsl):
// the GPU's 8-fetch form against the CPU's 64-weight sum, empty-space skipping still exact with
// its 2-voxel reach, and the grid-artefact metric (grid_artefacts.h) on the coarse storm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dlm_scenes.h"
#include "grid_artefacts.h"
#include "reference/ray_marcher.h"
#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "render_scenes.h"
#include "scene/scene_file.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

using ReconstructionTest = GlTest;
using scene::Reconstruction;

/// The demo's view (examples/scenes/demo.json.in): oblique preset, 40° field of view, sun from
/// azimuth 140° at 35°, heights × 8.
render::RenderOutput renderWith(const ExtinctionVolumes& v, const DemoView& d, Reconstruction r,
                                const render::RenderSettings& rs, double dlm_texel_voxels = 1.0) {
  return renderDemoView(v, d, rs, r, scene::Detail::None, dlm_texel_voxels);
}

// The GPU's tricubic B-spline from 8 trilinear fetches against the CPU reference ray marcher with
// the explicit 64-weight sum (same DLM, read back), coarse storm, demo view, no jitter. The
// differences are float vs double plus the GPU's linear-filter weights (on llvmpipe, float
// weights; GPUs with 8-bit filter fractions would be coarser, Sigg & Hadwiger §20.3).
TEST_F(ReconstructionTest, GpuCubicMatchesTheCpuReferenceRayMarcher) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 96, 54);
  auto tex = render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.reconstruction = Reconstruction::Cubic});
  EXPECT_EQ(tex.occupancy().dilation_voxels, 2);
  render::DeepLightMap dlm;
  dlm.build(tex, -d.sun.toSun(), scene::DlmSettings{});
  render::RenderSettings rs;
  rs.jitter = false;
  rs.empty_space_skipping = true;
  rs.reconstruction = Reconstruction::Cubic;
  rs.atmosphere = false;  // the CPU reference has issue 12's clear sky and no aerial perspective
  // Both stop their rays at the terrain (the generator's 700 m island; glsl/common/terrain.glsl on
  // both sides), but a march sample lying within float rounding of the stop is taken by one side
  // and not by the other: one pixel of cloud on the island's slope differed by a whole step
  // (0.026). The terrain's own GPU/CPU agreement is tests/render/terrain_gl_test.cpp's; here the
  // filter is under test, so the ground is the plane z = 0.
  rs.terrain = false;
  render::CloudRenderer renderer;
  const auto gpu = renderer.render(tex, dlm, d.camera, d.sun, rs);
  const auto map = dlm.readBack();
  const auto& ls = dlm.lightSpace();
  const auto cpu = reference::marchCloudLayer(
      v, d.frame, d.camera, d.sun, [&](const glm::dvec3& p) { return render::DeepLightMap::lookup(map, ls, p); }, rs);
  const LayerDifference diff = layerDifference(gpu.cloud_layer, cpu);
  std::printf("[ cubic    ] 96x54 coarse storm: coverage %.2f, max |GPU-CPU| %.2e, mean %.2e\n", diff.coverage,
              diff.max, diff.mean);
  EXPECT_GT(diff.coverage, 0.05) << "the camera must see the storm";
  EXPECT_LE(diff.mean, 1e-4);
  EXPECT_LE(diff.max, 0.02);
}

// Empty-space skipping stays exact with the cubic filter's 2-voxel reach (occupancy dilated by 2,
// grown boxes padded by 2): the image with skipping equals the one without, in the DLM and the
// eye pass, while skipping still saves samples.
TEST_F(ReconstructionTest, EmptySpaceSkippingGivesTheSameImageWithCubic) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 160, 90);
  render::RenderSettings rs;
  rs.jitter = false;
  rs.empty_space_skipping = true;
  const auto on = renderWith(v, d, Reconstruction::Cubic, rs);
  rs.empty_space_skipping = false;
  const auto off = renderWith(v, d, Reconstruction::Cubic, rs);
  const LayerDifference diff = layerDifference(on.cloud_layer, off.cloud_layer);
  const double maxErr = diff.max;
  std::printf("[ cubic    ] skipping on vs off: coverage %.2f, max |difference| %.2e\n", diff.coverage, maxErr);
  EXPECT_GT(diff.coverage, 0.05);
  // The DLMs with and without skipping agree within 2ε (dlm_gl_test EmptySpaceSkippingChangesNothing);
  // the eye pass reads them at the same points, so the layer differs by at most ~2ε·L.
  EXPECT_LE(maxErr, 2.0 * scene::DlmSettings{}.epsilon + 1e-5);
}

// Issue 13's "Done means" asks for ≥ 10× less power at the model's column spacing with the cubic
// filter, on the coarse storm at the demo's view (here closer: distance × 0.5, 640 × 360, so that a
// column spans ~6 pixels). Reference-preset view steps, no jitter, DLM texels of ¼ voxel
// (grid_artefacts.h). Measured on llvmpipe (docs/rendering.md "Reconstruction") on the storm with
// domed cells, anvils and a lens-shaped shield (data_tools/wrf_hurricane.cpp):
//   - single scattering, the filter alone: 2.6× in the band 0.75 … 1.25 cycles per column, 3.5× at
//     1.75 … 2.25 (the 10× of the issue is NOT reached at the column spacing by this metric);
//   - the default, two_stream (issue 12): trilinear 4.45, cubic 2.08 (2.1×; 3.3× at twice the
//     frequency) — the cubic filter reaches its column depths too (volume/column_depth.h; with
//     trilinear depths under a cubic field the cubic power was 6× trilinear's on the old storm);
//   - cubic two_stream has about half the power of cubic octaves (4.28), the default before.
// (Twelfth session: the sky term skyDiffuse — the sky the column reflects, read through the column
// depths — added harmonic power to the cubic field: at 1.75 … 2.25 the ratios were 5.5× single and
// 3.6× two_stream before it; the bounds below follow the new measurement.)
// The test holds these with a 20–25 % margin, so a regression of the filter or of the column
// depths' filter shows.
TEST_F(ReconstructionTest, CubicLowersTheGridArtefactsOfTheCoarseStorm) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 640, 360, 0.5);
  const double zMid_m = d.frame.min_m().z + 0.5 * d.frame.size_m().z;
  struct Power {
    double column, harmonic;  // bands 0.75 … 1.25 and 1.75 … 2.25 cycles per column
  };
  auto measure = [&](Reconstruction r, lighting::MultipleScattering ms) {
    render::RenderSettings rs;
    rs.jitter = false;
    rs.step_voxels = 0.25;
    rs.multiple_scattering = ms;
    const auto out = renderWith(v, d, r, rs, 0.25);
    return Power{gridArtefactPower(out.cloud_layer, d.camera, d.frame, zMid_m),
                 gridArtefactPower(out.cloud_layer, d.camera, d.frame, zMid_m, 1.75, 2.25)};
  };
  using lighting::MultipleScattering;
  const Power triSingle = measure(Reconstruction::Trilinear, MultipleScattering::Single);
  const Power cubSingle = measure(Reconstruction::Cubic, MultipleScattering::Single);
  const Power triTwo = measure(Reconstruction::Trilinear, MultipleScattering::TwoStream);
  const Power cubTwo = measure(Reconstruction::Cubic, MultipleScattering::TwoStream);
  const Power cubOctaves = measure(Reconstruction::Cubic, MultipleScattering::Octaves);
  std::printf("[ cubic    ] coarse storm 640x360, power at 0.75-1.25 / 1.75-2.25 cycles per column:\n"
              "             single: trilinear %.4g / %.4g, cubic %.4g / %.4g (ratios %.2f / %.2f)\n"
              "             two_stream: trilinear %.4g / %.4g, cubic %.4g / %.4g (ratios %.2f / %.2f)\n"
              "             octaves: cubic %.4g / %.4g\n",
              triSingle.column, triSingle.harmonic, cubSingle.column, cubSingle.harmonic,
              triSingle.column / cubSingle.column, triSingle.harmonic / cubSingle.harmonic, triTwo.column,
              triTwo.harmonic, cubTwo.column, cubTwo.harmonic, triTwo.column / cubTwo.column,
              triTwo.harmonic / cubTwo.harmonic, cubOctaves.column, cubOctaves.harmonic);
  EXPECT_GT(triSingle.column, 0.0);
  EXPECT_GE(triSingle.column, 1.85 * cubSingle.column);
  EXPECT_GE(triSingle.harmonic, 2.8 * cubSingle.harmonic);
  EXPECT_GE(triTwo.column, 1.8 * cubTwo.column);
  EXPECT_GE(triTwo.harmonic, 2.6 * cubTwo.harmonic);
  EXPECT_LE(cubTwo.column, 0.65 * cubOctaves.column);
  EXPECT_LE(cubTwo.harmonic, 0.85 * cubOctaves.harmonic);
}

}  // namespace
}  // namespace nph::test
