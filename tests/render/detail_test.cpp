// Procedural sub-grid detail on the CPU (issue 13 item 2; volume/detail.h): the per-column mass it
// keeps on the coarse storm, its controls from the storm's model fields, and the reach that keeps
// empty-space skipping conservative.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <tbb/parallel_for.h>

#include "dlm_scenes.h"
#include "volume/extinction_sampler.h"
#include "volume/occupancy.h"

namespace nph::test {
namespace {

using volume::Detail;

/// Per model column (i, j): the mean vertical optical depth over the column's footprint, from
/// `sub`² vertical rays at the centres of a sub-grid, each integrated with the midpoint rule at ¼ of
/// a layer from below to above the grown box (in the data's metres: the frame's heights divided by
/// its exaggeration).
std::vector<double> columnOpticalDepths(const volume::ExtinctionSampler& s, int sub) {
  const volume::VolumeFrame& f = s.frame();
  const glm::dvec3 voxel = f.voxel_size_m;
  const double reach = 2.0 + s.detail().reach_voxels;
  const double z0 = f.min_m().z - reach * voxel.z, z1 = f.max_m().z + reach * voxel.z;
  const double dz = 0.25 * voxel.z;
  const int steps = int(std::ceil((z1 - z0) / dz));
  std::vector<double> tau(std::size_t(f.voxels.x) * std::size_t(f.voxels.y), 0.0);
  tbb::parallel_for(0, f.voxels.y, [&](int j) {
    for (int i = 0; i < f.voxels.x; ++i) {
      double sum = 0.0;
      for (int b = 0; b < sub; ++b)
        for (int a = 0; a < sub; ++a) {
          const double x = (i + (a + 0.5) / sub) * voxel.x, y = (j + (b + 0.5) / sub) * voxel.y;
          for (int k = 0; k < steps; ++k) sum += s.at({x, y, z0 + (k + 0.5) * dz}).total();
        }
      tau[std::size_t(j) * std::size_t(f.voxels.x) + std::size_t(i)] =
          sum * dz / f.height_exaggeration / double(sub * sub);
    }
  });
  return tau;
}

// Issue 13 "Mass": per model column, the mean optical depth with detail within 5 % of the
// undetailed field — on the coarse storm (72×64 columns, 10 km, demo's × 8 heights), for every
// column of optical depth ≥ 1 (the visible cloud; thinner columns are reported). The density factor
// has mean 1 over the noise (detail.glsl) and its noise has 8+ cells per column, so a column keeps
// its mass up to the noise's sampling error; the displacement moves extinction by ≤ ¼ column.
TEST(Detail, KeepsTheOpticalDepthOfEveryModelColumn) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  const volume::ExtinctionSampler plain(v, f), full(v, f, volume::Reconstruction::Trilinear, Detail::Full);
  constexpr int kSub = 4;
  const std::vector<double> t0 = columnOpticalDepths(plain, kSub), t1 = columnOpticalDepths(full, kSub);
  double worst = 0.0, worstThin = 0.0, sum0 = 0.0, sum1 = 0.0;
  int columns = 0;
  std::vector<double> errors;
  for (std::size_t c = 0; c < t0.size(); ++c) {
    sum0 += t0[c];
    sum1 += t1[c];
    if (t0[c] < 0.1) continue;
    const double e = std::abs(t1[c] / t0[c] - 1.0);
    if (t0[c] >= 1.0) {
      worst = std::max(worst, e);
      errors.push_back(e);
      ++columns;
    } else {
      worstThin = std::max(worstThin, e);
    }
  }
  std::sort(errors.begin(), errors.end());
  const double p95 = errors.empty() ? 0.0 : errors[std::size_t(0.95 * double(errors.size() - 1))];
  std::printf("[ detail   ] coarse storm, %d columns with tau >= 1: max |change| %.2f %%, 95th pct %.2f %%; "
              "0.1 <= tau < 1: max %.2f %%; whole domain %.3f %%\n",
              columns, 100.0 * worst, 100.0 * p95, 100.0 * worstThin, 100.0 * (sum1 / sum0 - 1.0));
  ASSERT_GT(columns, 100) << "the storm must have optically thick columns";
  EXPECT_LE(worst, 0.05);
  EXPECT_LE(std::abs(sum1 / sum0 - 1.0), 0.01);
}

// The footprints with plain mass (P_J > 1e-6 of the largest, where solveDetailCorrection applies c)
// and their plain optical depth τ_J, from half-column masses measured with `pattern`.
struct Footprints {
  std::vector<double> tau;  ///< per model column; 0 where c does not apply
};
Footprints footprints(const volume::HalfColumnMasses& m, const volume::VolumeFrame& f, const volume::MassPattern& p) {
  Footprints out;
  const std::size_t hx = std::size_t(2 * m.nx);
  out.tau.assign(std::size_t(m.nx) * std::size_t(m.ny), 0.0);
  double maxPlain = 0.0;
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      double P = 0.0;
      for (int q = 0; q < 4; ++q) P += m.plain[std::size_t(2 * j + q / 2) * hx + std::size_t(2 * i + q % 2)];
      out.tau[std::size_t(j) * std::size_t(m.nx) + std::size_t(i)] = P;
      maxPlain = std::max(maxPlain, P);
    }
  const double perSum =
      p.step_layers * f.voxel_size_m.z / f.height_exaggeration / double(4 * p.rays_per_axis * p.rays_per_axis);
  for (double& t : out.tau) t = t > 1e-6 * maxPlain ? t * perSum : 0.0;
  return out;
}

// Issue 13, "a cheaper mass measurement" (volume/detail.h MassPattern, docs/detail.md): on the
// coarse storm (detail full, trilinear and cubic),
//  - marching only the occupied footprints and layers is exact: the skipped samples are zeros, so
//    the half-column masses and c are bit-identical to the exhaustive march's (4×4 rays per
//    column, ¼ layer, every footprint, the whole grown box: the tenth session's measurement);
//  - the pattern in use (kMassPattern: 4×4 rays per column, ½ layer, occupied only) gives a c_J
//    within 4 % of the exhaustive one on every footprint of τ ≥ 1 (measured: 1.45 % trilinear,
//    3.06 % cubic; rms ≤ 0.5 %, measured 0.11 / 0.17 %) and within 10 % on those of
//    0.1 ≤ τ < 1. |c/c_exh − 1| is the relative change of the footprint's corrected optical mass,
//    what the correction keeps. Thinner footprints (τ < 0.1: a neighbour's ramp that the shape
//    erodes to a sliver, c near its clamps) are reported, not bounded: they hold no visible mass.
TEST(Detail, CheaperMassMeasurementMatchesTheExhaustiveOne) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  for (const volume::Reconstruction r : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    const volume::ExtinctionSampler s(v, f, r, Detail::Full);
    const volume::HalfColumnMasses exhaustive = s.measureHalfColumnMasses(volume::kExhaustiveMassPattern);
    volume::MassPattern occupied = volume::kExhaustiveMassPattern;
    occupied.occupied_only = true;
    const volume::HalfColumnMasses skipped = s.measureHalfColumnMasses(occupied);
    const char* name = r == volume::Reconstruction::Cubic ? "cubic" : "trilinear";
    EXPECT_EQ(skipped.plain, exhaustive.plain) << name;
    EXPECT_EQ(skipped.detailed, exhaustive.detailed) << name;
    const std::vector<float> c0 = volume::solveDetailCorrection(exhaustive);
    EXPECT_EQ(volume::solveDetailCorrection(skipped), c0) << name;
    // The correction in use (the sampler's) against the exhaustive one.
    const std::vector<float>& c = s.detailCorrection();
    const Footprints fp = footprints(exhaustive, f, volume::kExhaustiveMassPattern);
    double maxThick = 0.0, sumThick = 0.0, maxThin = 0.0;
    int thick = 0, thin = 0, faint = 0, faintOver5 = 0;
    for (std::size_t J = 0; J < c0.size(); ++J) {
      if (!(fp.tau[J] > 0.0)) {
        EXPECT_EQ(c[J], 1.0f) << name << ": no plain mass, no correction";
        continue;
      }
      const double e = std::abs(double(c[J]) / double(c0[J]) - 1.0);
      if (fp.tau[J] >= 1.0) {
        maxThick = std::max(maxThick, e);
        sumThick += e * e;
        ++thick;
      } else if (fp.tau[J] >= 0.1) {
        maxThin = std::max(maxThin, e);
        ++thin;
      } else {
        ++faint;
        faintOver5 += e > 0.05;
      }
    }
    const double rmsThick = std::sqrt(sumThick / std::max(thick, 1));
    std::printf(
        "[ detail   ] %s: c of kMassPattern vs exhaustive: %d footprints with tau >= 1: max %.2f %% rms %.3f %%; "
        "%d with 0.1 <= tau < 1: max %.2f %%; %d thinner, %d of them off by > 5 %%\n",
        name, thick, 100.0 * maxThick, 100.0 * rmsThick, thin, 100.0 * maxThin, faint, faintOver5);
    ASSERT_GT(thick, 100) << name;
    EXPECT_LE(maxThick, 0.04) << name;
    EXPECT_LE(rmsThick, 0.005) << name;
    EXPECT_LE(maxThin, 0.10) << name;
  }
}

// The controls come from the storm's model fields (TKE_PBL, CLDFRA, W; volume/detail.h): the storm
// has deep convective cells and a stratiform shield, so both regimes occur, and CLDFRA < 1 somewhere.
TEST(Detail, ControlsSeeBothRegimesOfTheCoarseStorm) {
  const ExtinctionVolumes v = coarseStorm();
  ASSERT_EQ(v.tke_m2_per_s2.size(), v.voxelCount()) << "the storm carries TKE_PBL to the volume";
  ASSERT_EQ(v.cloud_fraction.size(), v.voxelCount()) << "the storm carries CLDFRA to the volume";
  ASSERT_EQ(v.wind_w_m_per_s.size(), v.voxelCount()) << "the storm carries W to the volume";
  const volume::DetailControls c = volume::buildDetailControls(v);
  int convective = 0, stratiform = 0, partly = 0;
  for (std::size_t q = 0; q < v.voxelCount(); ++q) {
    if (v.ice_per_m[q] + v.water_per_m[q] < 1e-4f) continue;
    convective += c.rgba[4 * q + 1] > 200;
    stratiform += c.rgba[4 * q + 1] < 50;
    partly += c.rgba[4 * q + 2] < 200;
  }
  std::printf("[ detail   ] cloudy voxels: %d convective, %d stratiform, %d with cloud fraction < 0.78\n", convective,
              stratiform, partly);
  EXPECT_GT(convective, 100);
  EXPECT_GT(stratiform, 100);
  EXPECT_GT(partly, 0);
  // Without the model fields (a .nph cache): the proxies (column contrast, hydrometeor gradient)
  // still find both regimes, and the cloud fraction is 1 (no acceptance).
  ExtinctionVolumes bare = v;
  bare.tke_m2_per_s2.clear();
  bare.cloud_fraction.clear();
  bare.wind_w_m_per_s.clear();
  const volume::DetailControls p = volume::buildDetailControls(bare);
  int proxyConvective = 0, proxyStratiform = 0, agree = 0, cloudy = 0;
  for (std::size_t q = 0; q < v.voxelCount(); ++q) {
    if (v.ice_per_m[q] + v.water_per_m[q] < 1e-4f) continue;
    ++cloudy;
    proxyConvective += p.rgba[4 * q + 1] > 200;
    proxyStratiform += p.rgba[4 * q + 1] < 50;
    agree += (p.rgba[4 * q + 1] > 127) == (c.rgba[4 * q + 1] > 127);
    EXPECT_EQ(p.rgba[4 * q + 2], 255);
  }
  std::printf("[ detail   ] proxies: %d convective, %d stratiform; regime as with W in %.1f %% of %d cloudy voxels\n",
              proxyConvective, proxyStratiform, 100.0 * agree / cloudy, cloudy);
  EXPECT_GT(proxyConvective, 100);
  EXPECT_GT(proxyStratiform, 100);
}

// Empty-space skipping stays conservative: the detailed field is 0 wherever the occupancy dilated by
// the filter's and the displacement's reach is 0, and never above the brick's maximum × 2·max c
// (ρ ≤ 2, c the mass correction; render::VolumeTextures::upload builds the same grid).
TEST(Detail, OccupancyBoundsTheDetailedField) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  const volume::ExtinctionSampler s(v, f, volume::Reconstruction::Trilinear, Detail::Full);
  const std::vector<float>& c = s.detailCorrection();
  const float scale = float(volume::kMaxDetailDensity) * *std::max_element(c.begin(), c.end());
  const volume::OccupancyGrid g =
      volume::buildOccupancy(v, 8, volume::Reconstruction::Trilinear, s.detail().reach_voxels, scale);
  int violations = 0, samples = 0;
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i)
        for (double o : {0.1, 0.6}) {
          const glm::dvec3 p = f.worldFromGrid({i + o, j + 1.0 - o, k + o});
          const double b = s.at(p).total();
          const double m = double(g.at(i / g.brick, j / g.brick, k / g.brick));
          ++samples;
          if (b > m * (1.0 + 1e-5)) ++violations;
        }
  std::printf("[ detail   ] occupancy bound: %d violations in %d samples\n", violations, samples);
  EXPECT_EQ(violations, 0);
}

}  // namespace
}  // namespace nph::test
