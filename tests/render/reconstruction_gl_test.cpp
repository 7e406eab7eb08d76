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
#include "volume/extinction_sampler.h"
#include "volume/spline_coefficients.h"

namespace nph::test {
namespace {

using ReconstructionTest = GlTest;
using volume::Reconstruction;

/// The demo's view (examples/scenes/demo.json.in): oblique preset, 40° field of view, sun from
/// azimuth 140° at 35°, heights × 8.
render::RenderOutput renderWith(const ExtinctionVolumes& v, const DemoView& d, Reconstruction r,
                                const render::RenderSettings& rs, double dlm_texel_voxels = 1.0) {
  return renderDemoView(v, d, rs, r, volume::Detail::None, dlm_texel_voxels);
}

// The GPU's tricubic B-spline from 8 trilinear fetches against the CPU reference ray marcher with
// the explicit 64-weight sum (same DLM, read back), coarse storm, demo view, no jitter. The
// differences are float vs double plus the GPU's linear-filter weights (on llvmpipe, float
// weights; GPUs with 8-bit filter fractions would be coarser, Sigg & Hadwiger §20.3).
TEST_F(ReconstructionTest, GpuCubicMatchesTheCpuReferenceRayMarcher) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 96, 54);
  // Both cubic filters: the B-spline of the voxels and of their interpolating spline coefficients
  // (volume/spline_coefficients.h: the upload and the CPU sampler each solve for them).
  for (const Reconstruction r : {Reconstruction::Cubic, Reconstruction::CubicInterpolating}) {
    SCOPED_TRACE(std::string(volume::kReconstructionNames[std::size_t(r)]));
    auto tex = render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.reconstruction = r});
    EXPECT_EQ(tex.occupancy().dilation_voxels, 2);
    render::DeepLightMap dlm;
    dlm.build(tex, -d.sun.toSun(), lighting::DlmSettings{});
    render::RenderSettings rs;
    rs.jitter = false;
    rs.empty_space_skipping = true;
    rs.reconstruction = r;
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
    std::printf("[ cubic    ] 96x54 coarse storm, %s: coverage %.2f, max |GPU-CPU| %.2e, mean %.2e\n",
                std::string(volume::kReconstructionNames[std::size_t(r)]).c_str(), diff.coverage, diff.max, diff.mean);
    EXPECT_GT(diff.coverage, 0.05) << "the camera must see the storm";
    EXPECT_LE(diff.mean, 1e-4);
    // A GPU's 8-bit filter weights in the B-spline's 8 trilinear fetches: 0.021 (cubic) and 0.032
    // (interpolating) on the H200 (softwareRasteriser).
    EXPECT_LE(diff.max, softwareRasteriser() ? 0.02 : 0.05);
  }
}

// volume/spline_coefficients.h on the CPU sampler: the interpolating spline passes through every
// voxel, the boundary ones included (the zero border is part of the solve); the plain B-spline
// does not (here it is off by several per cent, so the check can fail).
TEST(SplineCoefficients, TheInterpolatingSplinePassesThroughTheVoxels) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(11, 9, 7, 1000.0, 500.0, 0.0);
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i)
        v.water_per_m[v.index(i, j, k)] =
            float(1e-3 * (2.0 + std::sin(0.9 * i + 0.3) * std::cos(0.7 * j) + 0.5 * std::sin(1.1 * k)));
  v.updateMaxima();
  ExtinctionVolumes c = volume::splineCoefficientVolumes(v);
  ASSERT_EQ(c.water_per_m.size(), v.water_per_m.size());
  const volume::VolumeFrame f = volume::frameOf(v);
  const volume::ExtinctionSampler itp(v, f, Reconstruction::CubicInterpolating), cub(v, f, Reconstruction::Cubic);
  double errItp = 0.0, errCub = 0.0;
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const glm::dvec3 p = f.worldFromGrid({i + 0.5, j + 0.5, k + 0.5});
        const double s = v.water_per_m[v.index(i, j, k)];
        errItp = std::max(errItp, std::abs(itp.plainAt(p).water_per_m - s) / s);
        errCub = std::max(errCub, std::abs(cub.plainAt(p).water_per_m - s) / s);
      }
  std::printf("[ spline   ] largest relative error at the voxel centres: interpolating %.2e, B-spline %.2e\n", errItp,
              errCub);
  EXPECT_LE(errItp, 1e-5);
  EXPECT_GE(errCub, 0.05);
  // Where the field ends in clear air the spline rings: a lone voxel's neighbours get negative
  // coefficients, β is clamped at 0 and stays below the largest coefficient (the occupancy's bound).
  ExtinctionVolumes one = ExtinctionVolumes::zeros(5, 5, 5, 1000.0, 1000.0, 0.0);
  one.water_per_m[one.index(2, 2, 2)] = 1e-3f;
  one.updateMaxima();
  const volume::VolumeFrame f1 = volume::frameOf(one);
  const volume::ExtinctionSampler lone(one, f1, Reconstruction::CubicInterpolating);
  const float cmax = lone.voxels().max_water_per_m;
  for (int a = 0; a <= 40; ++a) {
    const double b = lone.plainAt(f1.worldFromGrid({2.5 + 0.05 * (a - 20), 2.5, 2.5})).water_per_m;
    EXPECT_GE(b, 0.0);
    EXPECT_LE(b, double(cmax) * (1.0 + 1e-9));
  }
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
  EXPECT_LE(maxErr, 2.0 * lighting::DlmSettings{}.epsilon + 1e-5);
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

// Issue 13's artefact metric against a grid-free truth (docs/rendering.md "A grid-free storm"). The
// analytic storm (dlm_scenes.h analyticStorm: smooth cells of σ = 1–2 columns, nothing at the column
// spacing) is sampled on the 10 km grid and rendered with each filter, and sampled on the 2.5 km
// grid for the reference (trilinear, DLM texels of one fine voxel). A rendition's difference from
// the reference is then the filter's error alone; its power is measured in three bands (cycles
// per column). Measured on llvmpipe (two_stream, 640 × 360, reference-preset steps, no jitter):
//   | band | trilinear | cubic B-spline | cubic_interpolating |
//   | 0.3 … 0.7 | 2.20e-2 | 8.02e-2 | 1.24e-3 |
//   | 0.8 … 1.2 | 4.15e-3 | 1.03e-2 | 6.39e-4 |
//   | 1.8 … 2.2 | 9.7e-4 | 2.16e-4 | 3.36e-5 |
// (default light settings here; nephele_grid_spectrum --analytic's two_stream table in docs/
// rendering.md has the same ratios within 10 %).
// The B-spline removes trilinear's kinks (4× less at twice the column frequency) but blurs the
// cells, which costs more than the kinks below 1.2 cycles per column; the interpolating spline
// keeps the cells and loses the kinks: 6.5× less than trilinear at the column spacing, 29× at its
// harmonic, 18× below it. Bounds with a ~25 % margin.
TEST_F(ReconstructionTest, CubicInterpolatingTracksAGridFreeStorm) {
  const ExtinctionVolumes storm = coarseStorm();
  const ExtinctionVolumes v = analyticStorm(storm), fine = analyticStorm(storm, 4);
  const DemoView d = demoView(v, 640, 360, 0.5), df = demoView(fine, 640, 360, 0.5);
  const double zMid_m = d.frame.min_m().z + 0.5 * d.frame.size_m().z;
  render::RenderSettings rs;
  rs.jitter = false;
  rs.step_voxels = 0.25;
  rs.terrain = false;
  const auto ref = renderDemoView(fine, df, rs, Reconstruction::Trilinear, volume::Detail::None, 1.0).cloud_layer;
  struct Bands {
    double low, column, harmonic;
  };
  auto error = [&](Reconstruction r) {
    const auto out = renderDemoView(v, d, rs, r, volume::Detail::None, 0.25).cloud_layer;
    const scene::RgbaImage e = layerMinus(out, ref);
    return Bands{gridArtefactPower(e, d.camera, d.frame, zMid_m, 0.3, 0.7),
                 gridArtefactPower(e, d.camera, d.frame, zMid_m, 0.8, 1.2),
                 gridArtefactPower(e, d.camera, d.frame, zMid_m, 1.8, 2.2)};
  };
  const Bands tri = error(Reconstruction::Trilinear), cub = error(Reconstruction::Cubic),
              itp = error(Reconstruction::CubicInterpolating);
  std::printf("[ spline   ] grid-free storm, power of the difference from the 2.5 km rendition at 0.3-0.7 / 0.8-1.2 / "
              "1.8-2.2 cycles per column:\n             trilinear %.3g / %.3g / %.3g, cubic %.3g / %.3g / %.3g, "
              "cubic_interpolating %.3g / %.3g / %.3g\n",
              tri.low, tri.column, tri.harmonic, cub.low, cub.column, cub.harmonic, itp.low, itp.column, itp.harmonic);
  EXPECT_GT(tri.column, 0.0);
  EXPECT_LE(itp.column, tri.column / 5.0);
  EXPECT_LE(itp.harmonic, tri.harmonic / 20.0);
  EXPECT_LE(itp.low, tri.low / 12.0);
  EXPECT_LE(itp.column, cub.column / 10.0);
  EXPECT_LE(cub.harmonic, tri.harmonic / 3.0);  // the B-spline's own gain (its kinks are gone)
}

}  // namespace
}  // namespace nph::test
