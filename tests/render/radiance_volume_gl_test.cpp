// The Monte Carlo radiance volume on the GPU (render/dlm/radiance_volume.h; issue 12, sixteenth
// session) against its CPU twin (reference/mc_radiance_volume.h) and the invariants the twin is
// tested on (tests/reference/mc_radiance_volume_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <utility>
#include <vector>

#include "core/error.h"
#include "dlm_scenes.h"
#include "reference/mc_radiance_volume.h"
#include "render/dlm/radiance_volume.h"
#include "render/dlm/volume_textures.h"
#include "render/gl/context.h"
#include "support/gl_fixture.h"
#include "volume/volume_frame.h"

namespace nph::test {
namespace {

using RadianceVolumeTest = GlTest;

// dlm_scenes.h's homogeneous slab with this test's spacing and an ice share.
ExtinctionVolumes box(int nx, int ny, int nz, double dx_m, double dz_m, float water_per_m, float ice_per_m) {
  ExtinctionVolumes v = homogeneousSlab(nx, ny, nz, water_per_m);
  v.dz_m = dz_m;
  v.georef.dx_m = dx_m;
  v.georef.dy_m = dx_m;
  std::fill(v.ice_per_m.begin(), v.ice_per_m.end(), ice_per_m);
  v.updateMaxima();
  return v;
}

// A box with structure (every 7th voxel without water), both phases, × 4 exaggeration.
ExtinctionVolumes structuredBox() {
  ExtinctionVolumes v = box(16, 16, 8, 200.0, 100.0, 0.01f, 0.002f);
  for (std::size_t i = 0; i < v.water_per_m.size(); i += 7) v.water_per_m[i] = 0.0f;
  return v;
}

// The GPU port itself, also on a software rasteriser (where Auto traces on the CPU), with the
// photons the test sets and no more (photons_per_column off).
render::RadianceVolumeSettings gpuBackend() {
  render::RadianceVolumeSettings s;
  s.backend = render::RadianceVolumeBackend::Gpu;
  s.photons_per_column = 0;
  return s;
}

const glm::dvec3 kObliqueSun = glm::normalize(glm::dvec3(-0.3, 0.5, 0.4));

reference::McRadianceVolume cpuVolume(const ExtinctionVolumes& v, const volume::VolumeFrame& frame,
                                      const glm::dvec3& toSun, const render::RadianceVolumeSettings& g,
                                      std::uint64_t seed, reference::McStats* stats = nullptr) {
  reference::McTallySpec spec;
  spec.coarsen_xy = g.coarsen_xy;
  spec.coarsen_z = g.coarsen_z;
  spec.min_order = g.min_order;
  spec.max_l = 4;
  reference::McSettings s;
  s.photons = g.photons;
  s.seed = seed;
  s.phase.ice = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, g.g_ice};
  s.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, g.g_water};
  return reference::traceMcRadianceVolumes(v, frame, toSun, {spec}, s, stats).front();
}

// RMS over the cells of the moments' difference, each moment k relative to the RMS of the
// reference's c_00 (the fluence's scale; the higher moments are signed and often near 0).
double rmsDifference(const std::vector<double>& a, const std::vector<double>& b, int k) {
  double d = 0.0, s = 0.0;
  const std::size_t cells = a.size() / render::kRadianceVolumeMoments;
  for (std::size_t c = 0; c < cells; ++c) {
    const double x = a[c * render::kRadianceVolumeMoments + std::size_t(k)];
    const double y = b[c * render::kRadianceVolumeMoments + std::size_t(k)];
    const double r = b[c * render::kRadianceVolumeMoments];
    d += (x - y) * (x - y);
    s += r * r;
  }
  return std::sqrt(d / s);
}

double sumOf(const std::vector<double>& m, int k) {
  double s = 0.0;
  for (std::size_t c = 0; c < m.size() / render::kRadianceVolumeMoments; ++c)
    s += m[c * render::kRadianceVolumeMoments + std::size_t(k)];
  return s;
}

// The GPU volume against the CPU twin with the same photons, grid, phases and convention (orders
// ≥ 1, l ≤ 4). Not bit-identical (float against double, other random streams), so statistically:
// the yardstick is the CPU twin against itself with another seed — two independent estimates with
// the same photon count differ by the photon noise alone, and so must the GPU's. Per moment the
// RMS difference over the 64 cells must stay within 1.5 × the seed-to-seed one (the RMS of 64
// cells is itself uncertain by ≈ 9 %; a bias of the port — a wrong power, cell volume, majorant,
// exaggeration or harmonic sign — is many times the noise), and the total fluence within 1 %.
TEST_F(RadianceVolumeTest, MatchesTheCpuTwinWithinThePhotonNoise) {
  const ExtinctionVolumes v = structuredBox();
  const volume::VolumeFrame frame = volume::frameOf(v, 4.0);
  render::RadianceVolumeSettings s = gpuBackend();
  s.photons = 1u << 17;
  s.min_order = 1;
  const auto tex = render::VolumeTextures::upload(v, frame, "twin");
  render::RadianceVolume gpu;
  ASSERT_TRUE(gpu.build(tex, kObliqueSun, s));
  EXPECT_EQ(gpu.stats().clamped, 0u);
  EXPECT_EQ(gpu.stats().truncated, 0u);
  reference::McStats cpuStats;
  const reference::McRadianceVolume a = cpuVolume(v, frame, kObliqueSun, s, 15, &cpuStats);
  // the same medium: collisions per photon within 1 %
  const double perPhotonGpu = double(gpu.stats().collisions) / double(s.photons);
  const double perPhotonCpu = double(cpuStats.collisions) / double(cpuStats.photons);
  EXPECT_NEAR(perPhotonGpu / perPhotonCpu, 1.0, 0.01)
      << "collisions per photon GPU " << perPhotonGpu << ", CPU " << perPhotonCpu;
  const reference::McRadianceVolume b = cpuVolume(v, frame, kObliqueSun, s, 16);
  ASSERT_EQ(gpu.cells(), a.cells);
  ASSERT_EQ(a.harmonics(), render::kRadianceVolumeMoments);
  const std::vector<float> g = gpu.readBackMoments();
  const std::vector<double> gd(g.begin(), g.end());
  for (int k = 0; k < render::kRadianceVolumeMoments; ++k) {
    const double noise = rmsDifference(b.moments, a.moments, k), port = rmsDifference(gd, a.moments, k);
    if (std::getenv("NPH_TEST_VERBOSE")) std::printf("moment %d: GPU-CPU %.4f CPU-CPU %.4f\n", k, port, noise);
    EXPECT_LT(port, 1.5 * noise + 1e-4) << "moment " << k << ": GPU−CPU " << port << ", CPU seed to seed " << noise;
  }
  const double total = sumOf(a.moments, 0);
  ASSERT_GT(total, 0.0);
  EXPECT_NEAR(sumOf(gd, 0) / total, 1.0, 0.01) << "total fluence, GPU over CPU";
  EXPECT_NEAR(sumOf(b.moments, 0) / total, 1.0, 0.01) << "total fluence, CPU seed 16 over seed 15";
  // The resolve is q·P/V times the integer sum, exactly (up to float's rounding of the result).
  const std::vector<std::int64_t> sums = gpu.readBackSums();
  ASSERT_EQ(sums.size(), g.size());
  for (std::size_t i = 0; i < sums.size(); i += 37)
    EXPECT_NEAR(g[i], double(sums[i]) * gpu.momentUnit(), 1e-6 * std::abs(double(sums[i]) * gpu.momentUnit()) + 1e-30);
}

// Seventeenth session (docs/accuracy.md "Seventeenth session"): llvmpipe ends every loop of a SIMD
// group past 65 535 back-edges (glsl/dlm/radiance_volume.comp, header); the sixteenth session's
// build lost the remaining collisions of photons that needed more, silently (on the hurricane 87
// collisions per photon against the twin's 98). Here every photon needs ≈ 10⁵ loop iterations at
// little cost: the sun straight above a column of clear air, 6.4 km deep, whose occupancy bricks
// all hold one dense voxel (β = 16 /m), so the majorant is 16 /m everywhere and a photon between
// the dense voxels makes ≈ 10⁵ null collisions on its way down to an opaque floor (τ = 10). Nearly
// every photon collides — at a dense voxel or the floor — in the CPU twin and in a build that
// traces every photon to its end; with the step budget off (one dispatch, as the sixteenth
// session's build) 0.06 of them, and loops cut short. 128 photons: the share's binomial standard
// deviation is < 0.02, the bound 0.05. With the default bricks and with bricks of 16 voxels (whose majorants the volume
// block misread before this session).
ExtinctionVolumes spikyColumn() {
  ExtinctionVolumes v = box(16, 16, 64, 1000.0, 100.0, 0.0f, 0.0f);
  for (int j = 0; j < v.ny; ++j)
    for (int i = 0; i < v.nx; ++i) v.water_per_m[std::size_t(j) * 16 + std::size_t(i)] = 0.1f;  // the floor
  for (int k = 3; k < v.nz; k += 8)
    for (int j = 3; j < v.ny; j += 8)
      for (int i = 3; i < v.nx; i += 8)
        v.water_per_m[(std::size_t(k) * 16 + std::size_t(j)) * 16 + std::size_t(i)] = 16.0f;
  v.updateMaxima();
  return v;
}

TEST_F(RadianceVolumeTest, PhotonsWithManyNullCollisionsAreNotCutShort) {
  const ExtinctionVolumes v = spikyColumn();
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  const glm::dvec3 overhead(0.0, 0.0, 1.0);
  render::RadianceVolumeSettings s = gpuBackend();
  s.photons = 128;
  reference::McStats cpuStats;
  cpuVolume(v, frame, overhead, s, 15, &cpuStats);
  const double cpuCollided = double(cpuStats.collided) / double(cpuStats.photons);
  EXPECT_GT(cpuCollided, 0.9);
  for (int brick : {8, 16}) {
    render::UploadOptions o;
    o.brick_voxels = brick;
    const auto tex = render::VolumeTextures::upload(v, frame, "spiky column", o);
    render::RadianceVolume gpu;
    ASSERT_TRUE(gpu.build(tex, overhead, s));
    const render::RadianceVolumeStats& st = gpu.stats();
    const double collided = double(st.collided) / double(s.photons);
    if (std::getenv("NPH_TEST_VERBOSE"))
      std::printf("bricks of %d: collided GPU %.3f CPU %.3f, collisions per photon GPU %.1f CPU %.1f, %d dispatches, "
                  "%.0f ms\n",
                  brick, collided, cpuCollided, double(st.collisions) / double(s.photons),
                  double(cpuStats.collisions) / double(cpuStats.photons), st.dispatches, st.build_ms);
    EXPECT_EQ(st.cut_short, 0u) << "bricks of " << brick;
    EXPECT_GT(st.dispatches, 1) << "the budget must pause photons here, or the case tests nothing";
    EXPECT_NEAR(collided, cpuCollided, 0.05) << "bricks of " << brick;
  }
}

// Integer sums are associative: the same photons give the same volume bit for bit however the
// invocations were scheduled; another seed does not. Seventeenth session: a photon's crossings are
// summed in registers while it stays in one cell and added once (glsl/dlm/radiance_volume.comp),
// so the sums are also those of the sixteenth session's one addition per crossing, bit for bit.
TEST_F(RadianceVolumeTest, SameSeedSameVolumeBitForBit) {
  const ExtinctionVolumes v = structuredBox();
  const volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "determinism");
  render::RadianceVolumeSettings s = gpuBackend();
  s.photons = 20000;
  render::RadianceVolume a, b, c;
  ASSERT_TRUE(a.build(tex, kObliqueSun, s));
  ASSERT_TRUE(b.build(tex, kObliqueSun, s));
  EXPECT_FALSE(a.build(tex, kObliqueSun, s)) << "an unchanged key must not rebuild";
  render::RadianceVolume everyCrossing(true);
  ASSERT_TRUE(everyCrossing.build(tex, kObliqueSun, s));
  EXPECT_EQ(a.readBackSums(), everyCrossing.readBackSums()) << "the tally runs against one addition per crossing";
  EXPECT_EQ(a.stats().collisions, everyCrossing.stats().collisions);
  s.seed = 17;
  ASSERT_TRUE(c.build(tex, kObliqueSun, s));
  const auto sa = a.readBackSums(), sb = b.readBackSums(), sc = c.readBackSums();
  EXPECT_EQ(sa, sb);
  EXPECT_NE(sa, sc);
  EXPECT_EQ(a.readBackMoments(), b.readBackMoments());
  EXPECT_GT(a.stats().collisions, 0u);
}

// A conservative slab lit from straight above (the CPU twin's test): the net vertical flux of all
// light, beam and every order (min_order 0), is the same at every depth (∂F_z/∂z = 0 in 1-D) and
// equals the transmitted share −(1 − R), R = 0.240 by δ-Eddington for τ = 5, g = 0.85 (the twin
// measures 0.761 against 0.760). Tolerances as the twin's, at the same photon count.
TEST_F(RadianceVolumeTest, ConservativeSlabCarriesTheSameNetFluxAtEveryDepth) {
  const ExtinctionVolumes v = box(32, 32, 8, 100.0, 25.0, 0.025f, 0.0f);  // τ = 5, 3.2 km × 200 m
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "slab");
  render::RadianceVolumeSettings s = gpuBackend();
  s.photons = 120000;
  s.min_order = 0;
  s.coarsen_xy = 8;
  s.coarsen_z = 1;
  render::RadianceVolume gpu;
  ASSERT_TRUE(gpu.build(tex, glm::dvec3(0, 0, 1), s));
  ASSERT_EQ(gpu.cells(), glm::ivec3(4, 4, 8));
  const std::vector<float> m = gpu.readBackMoments();
  const double norm = std::sqrt(4.0 * std::numbers::pi / 3.0);
  const double r = 0.240;
  double lo = 0.0, hi = -1.0;
  for (int k = 0; k < 8; ++k) {
    double fz = 0.0;  // the central 2 × 2 columns
    for (int j = 1; j <= 2; ++j)
      for (int i = 1; i <= 2; ++i)
        fz += 0.25 * double(m[std::size_t((k * 4 + j) * 4 + i) * render::kRadianceVolumeMoments + 2]) * norm;
    EXPECT_NEAR(fz, -(1.0 - r), 0.02) << "layer " << k;
    lo = std::min(lo, fz);
    hi = std::max(hi, fz);
  }
  EXPECT_LT(hi - lo, 0.01) << "the net flux changes with depth";
}

// Thirty-first session: on a software rasteriser the volume is traced by the CPU twin and uploaded
// (RadianceVolumeBackend). With the separate float textures (VolumeStorage::Reference) the field
// read back is the upload's bit for bit, so the uploaded moments are the twin's own run with the
// same seed, rounded to float, exactly; and the stats are the twin's.
TEST_F(RadianceVolumeTest, CpuBackendUploadsTheTwinsVolume) {
  const ExtinctionVolumes v = structuredBox();
  const volume::VolumeFrame frame = volume::frameOf(v, 4.0);
  render::UploadOptions o;
  o.storage = render::VolumeStorage::Reference;
  const auto tex = render::VolumeTextures::upload(v, frame, "cpu twin", o);
  const ExtinctionVolumes back = tex.readBackExtinction();
  EXPECT_EQ(back.ice_per_m, v.ice_per_m);
  EXPECT_EQ(back.water_per_m, v.water_per_m);
  render::RadianceVolumeSettings s;
  s.backend = render::RadianceVolumeBackend::Cpu;
  s.photons_per_column = 0;
  s.photons = 20000;
  s.seed = 15;
  render::RadianceVolume rv;
  ASSERT_TRUE(rv.build(tex, kObliqueSun, s));
  EXPECT_TRUE(rv.stats().cpu);
  EXPECT_TRUE(rv.readBackSums().empty());
  reference::McStats twinStats;
  const reference::McRadianceVolume twin = cpuVolume(v, frame, kObliqueSun, s, 15, &twinStats);
  ASSERT_EQ(rv.cells(), twin.cells);
  const std::vector<float> m = rv.readBackMoments();
  ASSERT_EQ(m.size(), twin.moments.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < m.size(); ++i) differ += m[i] != float(twin.moments[i]);
  EXPECT_EQ(differ, 0u) << "moments not the twin's";
  EXPECT_EQ(rv.stats().collisions, twinStats.collisions);
  EXPECT_EQ(rv.stats().collided, twinStats.collided);
  EXPECT_GT(twinStats.collisions, 0u);
  EXPECT_FALSE(rv.build(tex, kObliqueSun, s)) << "an unchanged key must not rebuild";
  s.backend = render::RadianceVolumeBackend::Gpu;
  EXPECT_TRUE(rv.build(tex, kObliqueSun, s)) << "the backend is part of the key";
  EXPECT_FALSE(rv.stats().cpu);
}

// The default (Compact) upload keeps β only as the packed texture's half floats: read back within
// half precision, and the CPU backend's volume (from those halves) against the GPU port's within
// the photon noise, measured as in MatchesTheCpuTwinWithinThePhotonNoise.
TEST_F(RadianceVolumeTest, CpuBackendOfACompactUploadMatchesTheGpuWithinThePhotonNoise) {
  const ExtinctionVolumes v = structuredBox();
  const volume::VolumeFrame frame = volume::frameOf(v, 4.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "compact");
  ASSERT_TRUE(tex.hasPacked());
  ASSERT_FALSE(tex.hasSeparateTextures());
  const ExtinctionVolumes back = tex.readBackExtinction();
  ASSERT_EQ(back.water_per_m.size(), v.water_per_m.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < v.water_per_m.size(); ++i)
    for (const auto& [a, b] : {std::pair{back.water_per_m[i], v.water_per_m[i]}, {back.ice_per_m[i], v.ice_per_m[i]}})
      worst = std::max(worst, double(std::abs(a - b)) / std::max(double(b), 1e-30));
  EXPECT_LT(worst, 1.0 / 1024.0) << "worst relative difference of the read-back β";  // half: 2⁻¹¹
  render::RadianceVolumeSettings s;
  s.photons = 1u << 16;
  s.photons_per_column = 0;
  s.min_order = 1;
  s.backend = render::RadianceVolumeBackend::Cpu;
  render::RadianceVolume cpuA, cpuB, gpu;
  ASSERT_TRUE(cpuA.build(tex, kObliqueSun, s));
  s.seed = 17;
  ASSERT_TRUE(cpuB.build(tex, kObliqueSun, s));
  s.backend = render::RadianceVolumeBackend::Gpu;
  ASSERT_TRUE(gpu.build(tex, kObliqueSun, s));
  const auto asDouble = [](const std::vector<float>& f) { return std::vector<double>(f.begin(), f.end()); };
  const std::vector<double> a = asDouble(cpuA.readBackMoments()), b = asDouble(cpuB.readBackMoments()),
                            g = asDouble(gpu.readBackMoments());
  for (int k = 0; k < render::kRadianceVolumeMoments; ++k) {
    const double noise = rmsDifference(b, a, k), port = rmsDifference(g, a, k);
    EXPECT_LT(port, 1.5 * noise + 1e-4) << "moment " << k << ": GPU−CPU " << port << ", CPU seed to seed " << noise;
  }
  const double total = sumOf(a, 0);
  ASSERT_GT(total, 0.0);
  EXPECT_NEAR(sumOf(g, 0) / total, 1.0, 0.01) << "total fluence, GPU over the CPU backend";
}

// Auto traces on the CPU exactly where the driver is a software rasteriser and the twin can trace
// the field; the interpolating spline's textures hold coefficients, so it stays on the GPU there
// and the CPU backend asked for it is a clear error.
TEST_F(RadianceVolumeTest, AutoTracesOnTheCpuOnASoftwareRasteriserOnly) {
  const ExtinctionVolumes v = structuredBox();
  const volume::VolumeFrame frame = volume::frameOf(v, 4.0);
  const render::RadianceVolumeSettings automatic;
  const auto tex = render::VolumeTextures::upload(v, frame, "auto");
  EXPECT_EQ(render::RadianceVolume::tracesOnCpu(tex, automatic), gl::softwareRasteriser());
  render::UploadOptions o;
  o.reconstruction = volume::Reconstruction::CubicInterpolating;
  const auto spline = render::VolumeTextures::upload(v, frame, "spline", o);
  EXPECT_FALSE(render::RadianceVolume::tracesOnCpu(spline, automatic));
  render::RadianceVolumeSettings cpu;
  cpu.backend = render::RadianceVolumeBackend::Cpu;
  cpu.photons = 64;
  render::RadianceVolume rv;
  EXPECT_THROW(rv.build(spline, kObliqueSun, cpu), nph::UsageError);
  o.reconstruction = volume::Reconstruction::Cubic;  // the B-spline reads the voxels: traceable
  const auto cubic = render::VolumeTextures::upload(v, frame, "cubic", o);
  EXPECT_TRUE(render::RadianceVolume::tracesOnCpu(cubic, cpu));
  EXPECT_TRUE(rv.build(cubic, kObliqueSun, cpu));
}

// A grid with more columns of cells than the accuracy scenes' gets photons_per_column a column:
// the count photonsFor gives is the one traced (stats) and in the key.
TEST_F(RadianceVolumeTest, LargerGridsGetPhotonsPerColumn) {
  render::RadianceVolumeSettings s;                                            // 65 536 photons, 64 a column
  EXPECT_EQ(render::RadianceVolume::photonsFor({24, 24, 20}, s), 65536u);      // the accuracy scenes
  EXPECT_EQ(render::RadianceVolume::photonsFor({125, 125, 39}, s), 1000000u);  // the demo storm
  EXPECT_EQ(render::RadianceVolume::photonsFor({4096, 4096, 2}, s), render::kRadianceVolumeMaxPhotons);
  s.photons_per_column = 0;
  EXPECT_EQ(render::RadianceVolume::photonsFor({125, 125, 39}, s), 65536u);
  const ExtinctionVolumes v = box(64, 48, 4, 200.0, 100.0, 0.01f, 0.0f);  // 16 × 12 columns of cells
  const auto tex = render::VolumeTextures::upload(v, volume::frameOf(v), "columns");
  s.photons = 100;
  s.photons_per_column = 8;
  render::RadianceVolume rv;
  ASSERT_TRUE(rv.build(tex, kObliqueSun, s));
  EXPECT_EQ(rv.stats().photons, 16u * 12u * 8u);
  EXPECT_NE(rv.cacheKey().find("|n=1536|"), std::string::npos) << rv.cacheKey();
}

TEST_F(RadianceVolumeTest, BadSettingsAreAClearError) {
  const ExtinctionVolumes v = structuredBox();
  const auto tex = render::VolumeTextures::upload(v, volume::frameOf(v), "bad");
  render::RadianceVolume gpu;
  render::RadianceVolumeSettings s = gpuBackend();
  s.photons = 0;
  EXPECT_THROW(gpu.build(tex, kObliqueSun, s), nph::UsageError);
  s = {};
  s.coarsen_z = 0;
  EXPECT_THROW(gpu.build(tex, kObliqueSun, s), nph::UsageError);
  s = {};
  s.g_water = 1.0f;
  EXPECT_THROW(gpu.build(tex, kObliqueSun, s), nph::UsageError);
  EXPECT_THROW(gpu.build(tex, glm::dvec3(0.0), render::RadianceVolumeSettings{}), nph::UsageError);
}

}  // namespace
}  // namespace nph::test
