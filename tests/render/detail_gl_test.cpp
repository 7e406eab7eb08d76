// Procedural sub-grid detail on the GPU (issue 13 item 2; volume/detail.h, glsl/common/detail.glsl):
// the noise tile of the compute shader against its CPU twin, the detailed field of the eye pass and
// the DLM against the CPU reference ray marcher, empty-space skipping still exact, and a still scene
// rendered twice bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "dlm_scenes.h"
#include "grid_artefacts.h"
#include "reference/ray_marcher.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/noise_texture.h"
#include "render/raycast/cloud_renderer.h"
#include "render_scenes.h"
#include "scene/scene_file.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"
#include "volume/detail.h"
#include "volume/extinction_sampler.h"
#include "volume/noise.h"

namespace nph::test {
namespace {

using DetailTest = GlTest;
using volume::Detail;

/// The demo's view (examples/scenes/demo.json.in): oblique preset, 40° field of view, sun from
/// azimuth 140° at 35°, heights × 8.
render::RenderOutput renderWith(const ExtinctionVolumes& v, const DemoView& d, Detail detail,
                                const render::RenderSettings& rs) {
  return renderDemoView(v, d, rs, rs.reconstruction, detail);
}

// The compute shader's tile against the CPU twin's (volume/noise.cpp: the same noise.glsl compiled
// as C++): integer hashes make the random numbers identical, float rounding after them may move a
// value across a quantisation step, so texels may differ by one code of 255, and rarely.
TEST_F(DetailTest, GpuNoiseTileMatchesTheCpuTwin) {
  const auto noise = render::NoiseTexture::generate();
  const int n = volume::kNoiseTexels;
  std::vector<std::uint8_t> gpu(std::size_t(4) * std::size_t(n) * std::size_t(n) * std::size_t(n));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(noise->texture().id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(gpu.size()), gpu.data());
  const std::vector<std::uint8_t>& cpu = volume::noiseVolume().rgba;
  ASSERT_EQ(gpu.size(), cpu.size());
  int maxDiff = 0;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const int d = std::abs(int(gpu[i]) - int(cpu[i]));
    maxDiff = std::max(maxDiff, d);
    differing += d != 0;
  }
  std::printf("[ detail   ] noise tile %d^3 RGBA8: max |GPU-CPU| %d codes, %zu of %zu values differ\n", n, maxDiff,
              differing, cpu.size());
  EXPECT_LE(maxDiff, 1);
  // A GPU rounds the stores' float→unorm8 its own way: 3.2 % of the values one code apart on the
  // H200 (softwareRasteriser), still never more than one code.
  EXPECT_LE(double(differing), (softwareRasteriser() ? 1e-3 : 0.05) * double(cpu.size()));
  // The mipmap chain (the detail's level of detail): made from the GPU's own level 0 by the CPU's
  // rule (render/dlm/noise_texture.cpp), so a level differs from the CPU twin's only where the box
  // of level-0 texels under it does — by one code at most.
  int maxMipDiff = 0;
  for (int k = 1; k < volume::kNoiseLevels; ++k) {
    const int m = n >> k;
    std::vector<std::uint8_t> level(std::size_t(4) * std::size_t(m) * std::size_t(m) * std::size_t(m));
    glGetTextureImage(noise->texture().id(), k, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(level.size()), level.data());
    const std::vector<std::uint8_t>& cpuLevel = volume::noiseVolume().mips[std::size_t(k - 1)];
    ASSERT_EQ(level.size(), cpuLevel.size());
    for (std::size_t i = 0; i < level.size(); ++i)
      maxMipDiff = std::max(maxMipDiff, std::abs(int(level[i]) - int(cpuLevel[i])));
  }
  std::printf("[ detail   ] noise mipmap levels 1-%d: max |GPU-CPU| %d codes\n", volume::kNoiseLevels - 1, maxMipDiff);
  EXPECT_LE(maxMipDiff, 1);
  GLint minFilter = 0;
  glGetTextureParameteriv(noise->texture().id(), GL_TEXTURE_MIN_FILTER, &minFilter);
  EXPECT_EQ(minFilter, GL_LINEAR_MIPMAP_LINEAR);
  // The channels are real noise (gradient fBm spans about 0.3 … 0.7, Worley fBm more).
  const volume::NoiseStats& s = volume::noiseVolume().stats;
  for (const volume::NoiseTermStats* t : {&s.r, &s.g, &s.a}) EXPECT_GT(t->half_range, 0.15);
}

// The detailed field in the eye pass and the DLM (glsl/dlm/volume.glsl extinctionAt) against the
// CPU reference ray marcher with ExtinctionSampler's twin (same detail.glsl, the CPU noise tile,
// the same RGBA8 controls), reading back the same DLM: coarse storm, demo view, no jitter. The
// differences: float vs double positions, one-code noise texels, the GPU's filter weights.
// The storm's U, V advect the noise (volume/detail.h DetailFlow); its clock is moved to 0.3 of a
// flow period after its 12 UTC (where phase a is invisible), so both phases and their blend are
// read, on both sides.
TEST_F(DetailTest, GpuDetailMatchesTheCpuReferenceRayMarcher) {
  ExtinctionVolumes v = coarseStorm();
  ASSERT_EQ(v.wind_u_m_per_s.size(), v.voxelCount());
  v.detail_clock_s += 0.3 * volume::kDetailFlowPeriod_s;
  const volume::DetailFlow flow = volume::detailFlow(v.detail_clock_s, true);
  ASSERT_GT(flow.weight_a, 0.5);
  ASSERT_LT(flow.weight_a, 0.7);
  const DemoView d = demoView(v, 96, 54);
  auto tex = render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.detail = Detail::Full});
  EXPECT_EQ(tex.occupancy().dilation_voxels, 1 + tex.detail().reach_voxels);
  render::DeepLightMap dlm;
  dlm.build(tex, -d.sun.toSun(), lighting::DlmSettings{});
  render::RenderSettings rs;
  rs.jitter = false;
  rs.detail = Detail::Full;
  rs.atmosphere = false;  // the CPU reference has issue 12's clear sky and no aerial perspective
  render::CloudRenderer renderer;
  const auto gpu = renderer.render(tex, dlm, d.camera, d.sun, rs);
  const auto map = dlm.readBack();
  const auto& ls = dlm.lightSpace();
  const auto cpu = reference::marchCloudLayer(
      v, d.frame, d.camera, d.sun, [&](const glm::dvec3& p) { return render::DeepLightMap::lookup(map, ls, p); }, rs);
  const LayerDifference diff = layerDifference(gpu.cloud_layer, cpu);
  std::printf("[ detail   ] 96x54 coarse storm, detail full: coverage %.2f, max |GPU-CPU| %.2e, mean %.2e\n",
              diff.coverage, diff.max, diff.mean);
  EXPECT_GT(diff.coverage, 0.05) << "the camera must see the storm";
  EXPECT_LE(diff.mean, 1e-3);
  EXPECT_LE(diff.max, 0.05);
  // And the detail changes the picture (the comparison above is not between two plain fields).
  rs.detail = Detail::None;
  const auto plain = renderWith(v, d, Detail::None, rs);
  EXPECT_GT(layerDifference(gpu.cloud_layer, plain.cloud_layer).mean, 10.0 * diff.mean);
}

// The GPU's mass measurement (glsl/render/detail_mass.comp; volume/detail.h MassPattern) against
// the CPU twin's (ExtinctionSampler::measureRayMasses), coarse storm, detail full, both
// filters: with the pattern in use, the same footprints are measured (the skipped ones are exactly
// 0 on both sides) and c agrees within 8 % on the footprints of τ ≥ 1 (measured 2.8 % trilinear,
// 5.5 % cubic: float positions, one-code noise texels and the GPU's filter weights move the shape's
// smoothstep edge, as in GpuDetailMatchesTheCpuReferenceRayMarcher); and on the GPU too the occupied-only march is
// exact — bit-identical masses to the march over every footprint and the whole grown box (here with
// a cheap 1-ray, 1-layer lattice, the skip does not depend on the lattice).
TEST_F(DetailTest, GpuMassMeasurementMatchesTheCpuTwinAndSkipsOnlyZeros) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  for (const volume::Reconstruction r : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    const char* name = r == volume::Reconstruction::Cubic ? "cubic" : "trilinear";
    const auto tex =
        render::VolumeTextures::upload(v, f, "coarse-storm", {.reconstruction = r, .detail = Detail::Full});
    const volume::ExtinctionSampler s(v, f, r, Detail::Full);
    const volume::RayMasses gpu = tex.measureRayMasses(v, volume::kMassPattern),
                            cpu = s.measureRayMasses(volume::kMassPattern);
    ASSERT_EQ(gpu.plain.size(), cpu.plain.size());
    int zeros = 0;
    for (std::size_t h = 0; h < cpu.plain.size(); ++h) {
      const bool skipped = cpu.plain[h] == 0.0 && cpu.detailed[h] == 0.0;
      zeros += skipped;
      if (skipped) {
        EXPECT_EQ(gpu.plain[h], 0.0) << name << " ray " << h;
        EXPECT_EQ(gpu.detailed[h], 0.0) << name << " ray " << h;
      }
    }
    // c on the footprints of τ ≥ 1 (the visible cloud; thinner ones sit near the clamps, where a
    // float-rounded sliver flips c).
    const std::vector<float> cg = volume::solveDetailCorrection(gpu), &cc = s.detailCorrection();
    const double tauPerSum = volume::kMassPattern.step_layers * f.voxel_size_m.z / f.height_exaggeration /
                             double(4 * volume::kMassPattern.rays_per_axis * volume::kMassPattern.rays_per_axis);
    double worst = 0.0;
    int thick = 0;
    for (std::size_t J = 0; J < cc.size(); ++J) {
      const double P = cpu.plainOf(int(J % std::size_t(v.nx)), int(J / std::size_t(v.nx)));
      if (P * tauPerSum < 1.0) continue;
      ++thick;
      worst = std::max(worst, std::abs(double(cg[J]) / double(cc[J]) - 1.0));
    }
    std::printf("[ detail   ] %s: mass measurement GPU vs CPU twin: c on %d footprints with tau >= 1: max rel. "
                "difference %.2e; %d of %zu rays skipped\n",
                name, thick, worst, zeros, cpu.plain.size());
    EXPECT_GT(thick, 100) << name;
    EXPECT_GT(zeros, 0) << name;
    EXPECT_LE(worst, 0.08) << name;
    const volume::MassPattern cheap{1, 1.0, true}, everywhere{1, 1.0, false};
    const volume::RayMasses a = tex.measureRayMasses(v, cheap), b = tex.measureRayMasses(v, everywhere);
    EXPECT_EQ(a.plain, b.plain) << name;
    EXPECT_EQ(a.detailed, b.detailed) << name;
  }
}

// Empty-space skipping stays exact with the detail: the occupancy is dilated by the displacement's
// reach and its maxima doubled (ρ ≤ 2), so the image with skipping equals the one without.
TEST_F(DetailTest, EmptySpaceSkippingGivesTheSameImageWithDetail) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 160, 90);
  render::RenderSettings rs;
  rs.jitter = false;
  rs.empty_space_skipping = true;
  const auto on = renderWith(v, d, Detail::Full, rs);
  rs.empty_space_skipping = false;
  const auto off = renderWith(v, d, Detail::Full, rs);
  const LayerDifference diff = layerDifference(on.cloud_layer, off.cloud_layer);
  std::printf("[ detail   ] skipping on vs off: coverage %.2f, max |difference| %.2e\n", diff.coverage, diff.max);
  EXPECT_GT(diff.coverage, 0.05);
  // As for the cubic filter (reconstruction_gl_test): the DLMs agree within 2ε.
  EXPECT_LE(diff.max, 2.0 * lighting::DlmSettings{}.epsilon + 1e-5);
}

// Temporal coherence, still scene: the noise is addressed in world metres and generated from
// integer hashes, so two frames of fixed data and camera are bit-identical (jitter on, as rendered).
TEST_F(DetailTest, StillSceneIsBitIdenticalFrameToFrame) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 96, 54);
  render::RenderSettings rs;
  auto tex = render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.detail = Detail::Full});
  render::DeepLightMap dlm;
  dlm.build(tex, -d.sun.toSun(), lighting::DlmSettings{});
  render::CloudRenderer renderer;
  const auto a = renderer.render(tex, dlm, d.camera, d.sun, rs);
  const auto b = renderer.render(tex, dlm, d.camera, d.sun, rs);
  EXPECT_EQ(a.cloud_layer.rgba, b.cloud_layer.rgba);
  // A second upload regenerating the tile gives the same frame too.
  auto tex2 = render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.detail = Detail::Full});
  render::DeepLightMap dlm2;
  dlm2.build(tex2, -d.sun.toSun(), lighting::DlmSettings{});
  const auto c = renderer.render(tex2, dlm2, d.camera, d.sun, rs);
  EXPECT_EQ(a.cloud_layer.rgba, c.cloud_layer.rgba);
}

// Still air reads the noise once (DETAIL_WIND_ON, glsl/common/detail_field.glsl): without U, V both
// flow phases are the same read with phase a's weight 1. The same storm with a wind of zero
// everywhere takes the two-read path (its wind texture exists: SPEC_DETAIL_WIND 1 in the eye pass,
// u_detail_flow.w = 1 in the DLM passes and the CPU twin); at a clock where phase a's weight is
// exactly 1 (φ = ½: half a flow period) its blend mix(b, a, 1) is a bit for bit. So the two
// programs must give the same frame, and the CPU twin the same field, bit for bit.
TEST_F(DetailTest, StillAirReadsTheNoiseOnceForTheSameField) {
  ExtinctionVolumes still = coarseStorm();
  ASSERT_FALSE(still.wind_u_m_per_s.empty());
  ExtinctionVolumes calm = still;
  still.wind_u_m_per_s.clear();
  still.wind_v_m_per_s.clear();
  std::fill(calm.wind_u_m_per_s.begin(), calm.wind_u_m_per_s.end(), 0.0f);
  std::fill(calm.wind_v_m_per_s.begin(), calm.wind_v_m_per_s.end(), 0.0f);
  still.detail_clock_s = calm.detail_clock_s = 0.5 * volume::kDetailFlowPeriod_s;
  ASSERT_EQ(volume::detailFlow(calm.detail_clock_s, true).weight_a, 1.0);
  const DemoView d = demoView(still, 96, 54);
  render::RenderSettings rs;
  rs.jitter = false;
  render::RenderOutput out[2];
  for (int k = 0; k < 2; ++k) {
    const ExtinctionVolumes& v = k == 0 ? still : calm;
    auto tex = render::VolumeTextures::upload(v, d.frame, k == 0 ? "still" : "calm", {.detail = Detail::Full});
    EXPECT_EQ(tex.hasDetailWind(), k == 1);
    render::DeepLightMap dlm;
    dlm.build(tex, -d.sun.toSun(), lighting::DlmSettings{});
    render::CloudRenderer renderer;
    EXPECT_EQ(renderer.features(tex, dlm, rs).detail_wind, k == 1);
    out[k] = renderer.render(tex, dlm, d.camera, d.sun, rs);
  }
  EXPECT_EQ(out[0].cloud_layer.rgba, out[1].cloud_layer.rgba);
  double alpha = 0.0;
  for (std::size_t i = 3; i < out[0].cloud_layer.rgba.size(); i += 4) alpha += double(out[0].cloud_layer.rgba[i]);
  EXPECT_GT(alpha, 10.0);  // the storm is in the frame
  // The CPU twin on a lattice through the storm.
  const volume::ExtinctionSampler a(still, d.frame, volume::Reconstruction::Trilinear, Detail::Full);
  const volume::ExtinctionSampler b(calm, d.frame, volume::Reconstruction::Trilinear, Detail::Full);
  int cloudy = 0;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j)
      for (int k = 0; k < 12; ++k) {
        const glm::dvec3 p = d.frame.worldFromGrid(
            {(i + 0.37) * still.nx / 24.0, (j + 0.61) * still.ny / 24.0, (k + 0.5) * still.nz / 12.0});
        const volume::ExtinctionSample x = a.at(p), y = b.at(p);
        ASSERT_EQ(x.ice_per_m, y.ice_per_m);
        ASSERT_EQ(x.water_per_m, y.water_per_m);
        cloudy += x.ice_per_m + x.water_per_m > 0.0;
      }
  EXPECT_GT(cloudy, 100);
}

// Issue 13 "Artefact metric" with the detail on (tests/render/grid_artefacts.h, docs/rendering.md):
// power at 0.75–1.25 cycles per model column on the coarse storm, demo view at half its distance,
// 640 × 360, ¼-voxel steps and DLM texels, no jitter, trilinear; of the alpha over the whole cloud
// layer (the silhouette, which the detail's shape rounds) and of the luminance in opaque runs (the
// metric of ReconstructionTest; the detail's texture adds broadband power there, reported, see
// docs/detail.md). The shape must not add silhouette power at the column spacing: measured 763 with
// full detail against 802 without (−5 %), so the bound is "no more than without".
TEST_F(DetailTest, ShapeDoesNotRaiseTheGridArtefactsOfTheCoarseStorm) {
  const ExtinctionVolumes v = coarseStorm();
  const DemoView d = demoView(v, 640, 360, 0.5);
  render::RenderSettings rs;
  rs.jitter = false;
  rs.step_voxels = 0.25;
  const double zMid_m = d.frame.min_m().z + 0.5 * d.frame.size_m().z;
  std::vector<double> band;
  for (int k = 0; k <= 10; ++k) band.push_back(0.75 + 0.05 * k);
  double alpha[2] = {0.0, 0.0}, luminance[2] = {0.0, 0.0};
  for (int on = 0; on < 2; ++on) {
    rs.detail = on ? Detail::Full : Detail::None;
    const auto out = renderDemoView(v, d, rs, volume::Reconstruction::Trilinear, rs.detail, 0.25);
    luminance[on] = gridArtefactPower(out.cloud_layer, d.camera, d.frame, zMid_m);
    for (double p : gridPowerSpectrum(out.cloud_layer, d.camera, d.frame, zMid_m, band, 3, 0.0)) alpha[on] += p;
  }
  std::printf("[ detail   ] grid artefacts 0.75-1.25 cycles/column, trilinear: alpha none %.4g, full %.4g; "
              "luminance none %.4g, full %.4g\n",
              alpha[0], alpha[1], luminance[0], luminance[1]);
  EXPECT_GT(alpha[0], 0.0) << "the camera must see the storm";
  EXPECT_LE(alpha[1], alpha[0]);
}

}  // namespace
}  // namespace nph::test
