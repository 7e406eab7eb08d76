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
#include "volume/noise.h"
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

// The seams of the twentieth session (docs/detail.md "Seams at column faces"): with c constant per
// column, the detailed field jumped by c_K/c_J at every face between two corrected columns — straight
// brightness steps where an anvil's edge is optically thin. Now c blends across a band at the faces
// (volume/detail.h "Mass"). On the coarse storm, detail full, at every face between two corrected
// columns whose c differ by more than 5 % (so a step would show; the test requires ≥ 50 such
// faces), at 9 heights through the cloud and three points along the face:
//  - the correction is continuous: |c(face − ε) − c(face + ε)| ≤ 6.3·10⁻⁴ of the old step
//    |c_K − c_J| (ε = 10⁻⁴ column; the blend's slope at the face is 1.5 per band half-width
//    kCorrectionBand = ¼, i.e. 3 per column: 6·10⁻⁴ over 2ε);
//  - so is the field: |β(face − ε) − β(face + ε)| ≤ 3·|β(face + 3ε) − β(face + ε)| + 0.1 % of β
//    + 10⁻⁸ /m — no larger than the field's own change over the same width beside the face (3×
//    for its curvature); the old correction's step was ≥ 5 % of β there;
//  - in a column's core (within ¼ column of its centre) c is the column's c_J exactly.
TEST(Detail, CorrectionHasNoStepAtColumnFaces) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  const volume::ExtinctionSampler s(v, f, volume::Reconstruction::Trilinear, Detail::Full);
  const std::vector<float>& c = s.detailCorrection();
  const int nx = v.nx, ny = v.ny;
  auto cOf = [&](int i, int j) { return double(c[std::size_t(j) * std::size_t(nx) + std::size_t(i)]); };
  const double eps = 1e-4;
  int faces = 0, samples = 0;
  double worstC = 0.0, worstBeta = 0.0, worstCore = 0.0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const double a = cOf(i, j), b = cOf(i + 1, j);
      if (a == 1.0 || b == 1.0 || std::abs(b / a - 1.0) < 0.05) continue;
      ++faces;
      for (const double y : {-0.2, 0.0, 0.2}) {
        const glm::dvec2 left(i + 0.5 - eps, j + y), right(i + 0.5 + eps, j + y);  // column centres at integers
        const double cl = volume::correctionAt(c, nx, ny, left), cr = volume::correctionAt(c, nx, ny, right);
        worstC = std::max(worstC, std::abs(cl - cr) / std::abs(b - a));
        for (int k = 0; k < 9; ++k) {
          const double gz = (k + 0.5) / 9.0 * v.nz;
          const double bl = s.at(f.worldFromGrid({left.x + 0.5, left.y + 0.5, gz})).total(),
                       br = s.at(f.worldFromGrid({right.x + 0.5, right.y + 0.5, gz})).total();
          if (std::max(bl, br) <= 0.0) continue;
          // A step, not the field's own slope: the difference across the face against the
          // difference over the next 2ε beside it (β is smooth there; the shape's smoothstep makes
          // it steep at the visible edge, so no fixed bound serves), plus 0.1 % of β and 10⁻⁸ /m
          // (τ = 10⁻⁴ over 10 km: the shape's last faint rim, where it reaches 0 within 3ε).
          const double br3 = s.at(f.worldFromGrid({right.x + 2.0 * eps + 0.5, right.y + 0.5, gz})).total();
          ++samples;
          const double jump = std::abs(bl - br) / (3.0 * std::abs(br3 - br) + 1e-3 * std::max(bl, br) + 1e-8);
          worstBeta = std::max(worstBeta, jump);
        }
      }
      for (const glm::dvec2 core : {glm::dvec2(0.0), glm::dvec2(0.24, -0.24), glm::dvec2(-0.24, 0.1)}) {
        worstCore = std::max(worstCore, std::abs(volume::correctionAt(c, nx, ny, glm::dvec2(i, j) + core) - a));
      }
    }
  std::printf("[ detail   ] %d faces with a c step > 5 %%: c across them within %.2e of the step, beta's jump %.2f of "
              "its bound (%d "
              "samples); "
              "cores off by %.1e\n",
              faces, worstC, worstBeta, samples, worstCore);
  ASSERT_GE(faces, 50);
  ASSERT_GT(samples, 100);
  EXPECT_LE(worstC, 6.3e-4);
  EXPECT_LE(worstBeta, 1.0);
  EXPECT_EQ(worstCore, 0.0);
}

// The footprints with plain mass (P_J > 1e-6 of the largest, where solveDetailCorrection applies c)
// and their plain optical depth τ_J, from ray masses measured with `pattern`.
struct Footprints {
  std::vector<double> tau;  ///< per model column; 0 where c does not apply
};
Footprints footprints(const volume::RayMasses& m, const volume::VolumeFrame& f, const volume::MassPattern& p) {
  Footprints out;
  out.tau.assign(std::size_t(m.nx) * std::size_t(m.ny), 0.0);
  double maxPlain = 0.0;
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      const double P = m.plainOf(i, j);
      out.tau[std::size_t(j) * std::size_t(m.nx) + std::size_t(i)] = P;
      maxPlain = std::max(maxPlain, P);
    }
  const double perSum =
      p.step_layers * f.voxel_size_m.z / f.height_exaggeration / double(4 * p.rays_per_axis * p.rays_per_axis);
  for (double& t : out.tau) t = t > 1e-6 * maxPlain ? t * perSum : 0.0;
  return out;
}

// Σ_{r∈J} d_r·c(x_r): footprint (i, j)'s detailed mass under the correction c, on the rays of `m`
// (volume/detail.h "Mass").
double correctedMass(const volume::RayMasses& m, const std::vector<float>& c, int i, int j) {
  const int R = m.rays_per_column;
  double sum = 0.0;
  for (int b = 0; b < R; ++b)
    for (int a = 0; a < R; ++a) {
      const glm::dvec2 g(i + (a + 0.5) / R - 0.5, j + (b + 0.5) / R - 0.5);
      sum += m.detailed[m.index(i, j, a, b)] * volume::correctionAt(c, m.nx, m.ny, g);
    }
  return sum;
}

// Issue 13, "a cheaper mass measurement" (volume/detail.h MassPattern, docs/detail.md): on the
// coarse storm (detail full, trilinear and cubic),
//  - marching only the occupied footprints and layers is exact: the skipped samples are zeros, so
//    the half-column masses and c are bit-identical to the exhaustive march's (4×4 rays per
//    column, ¼ layer, every footprint, the whole grown box: the tenth session's measurement);
//  - the pattern in use (kMassPattern: 4×4 rays per column, ½ layer, occupied only) gives a c_J
//    within 4 % of the exhaustive one on every footprint of τ ≥ 1 (measured: 1.45 % trilinear,
//    3.06 % cubic; rms ≤ 0.5 %, measured 0.11 / 0.17 %) and within 15 % on those of
//    0.1 ≤ τ < 1 (10 % until the noise was advected with the wind: the storm's U, V move it by
//    u·900 s at 12 UTC, another realisation of the noise, and the cubic thin footprints' sampling
//    error went from 5.6 % to 11.8 %; thick ones 3.06 → 3.24 %, rms 0.17 → 0.16 %).
//    The error is that of the footprint's corrected optical mass, what the correction keeps:
//    M_J(c) = Σ_{r∈J} d_r·c(x_r) over the exhaustive pattern's rays (the same positions), with c
//    blended between columns at their faces (twentieth session; before, c was constant per
//    column and the error was |c/c_exh − 1|), against M_J(c_exh). Thinner footprints (τ < 0.1: a neighbour's ramp that
//    the shape erodes to a sliver, c near its clamps) are reported, not bounded: they hold no visible mass.
TEST(Detail, CheaperMassMeasurementMatchesTheExhaustiveOne) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  for (const volume::Reconstruction r : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    const volume::ExtinctionSampler s(v, f, r, Detail::Full);
    const volume::RayMasses exhaustive = s.measureRayMasses(volume::kExhaustiveMassPattern);
    volume::MassPattern occupied = volume::kExhaustiveMassPattern;
    occupied.occupied_only = true;
    const volume::RayMasses skipped = s.measureRayMasses(occupied);
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
      const int i = int(J % std::size_t(v.nx)), j = int(J / std::size_t(v.nx));
      const double e = std::abs(correctedMass(exhaustive, c, i, j) / correctedMass(exhaustive, c0, i, j) - 1.0);
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
    std::printf("[ detail   ] %s: footprint mass under kMassPattern's c vs the exhaustive c: %d footprints with tau >= "
                "1: max %.2f %% rms %.3f %%; "
                "%d with 0.1 <= tau < 1: max %.2f %%; %d thinner, %d of them off by > 5 %%\n",
                name, thick, 100.0 * maxThick, 100.0 * rmsThick, thin, 100.0 * maxThin, faint, faintOver5);
    ASSERT_GT(thick, 100) << name;
    EXPECT_LE(maxThick, 0.04) << name;
    EXPECT_LE(rmsThick, 0.005) << name;
    EXPECT_LE(maxThin, 0.15) << name;
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

// ---- Coherence: the noise advected with the wind (volume/detail.h DetailFlow) ----

// The flow map's two phases: weights in [0, 1], each phase's weight 0 where its τ resets, τ growing
// with the clock at rate 1 in between (so the blended noise is continuous in time), and the
// world-fixed noise (τ = 0, weight 1) without a wind.
TEST(Detail, FlowPhasesFadeOutWhereTheyReset) {
  const double T = volume::kDetailFlowPeriod_s;
  const volume::DetailFlow calm = volume::detailFlow(12345.0, false);
  EXPECT_EQ(calm.tau_s, glm::dvec2(0.0));
  EXPECT_EQ(calm.weight_a, 1.0);
  const volume::DetailFlow at0 = volume::detailFlow(7.0 * T, true), atHalf = volume::detailFlow(7.5 * T, true);
  EXPECT_EQ(at0.tau_s.x, 0.0);      // phase a resets ...
  EXPECT_EQ(at0.weight_a, 0.0);     // ... unseen
  EXPECT_EQ(atHalf.tau_s.y, 0.0);   // phase b resets ...
  EXPECT_EQ(atHalf.weight_a, 1.0);  // ... unseen
  const double dt = 1.0;
  for (double t = 3.0 * T; t < 5.0 * T; t += 7.3) {
    const volume::DetailFlow f0 = volume::detailFlow(t, true), f1 = volume::detailFlow(t + dt, true);
    ASSERT_GE(f0.weight_a, 0.0);
    ASSERT_LE(f0.weight_a, 1.0);
    EXPECT_NEAR(std::abs(f1.weight_a - f0.weight_a), 2.0 * dt / T, 1e-9);  // triangular
    for (int p = 0; p < 2; ++p) {
      const double w0 = p == 0 ? f0.weight_a : 1.0 - f0.weight_a, w1 = p == 0 ? f1.weight_a : 1.0 - f1.weight_a;
      if (f1.tau_s[p] < f0.tau_s[p]) {
        EXPECT_LE(std::min(w0, w1), 2.0 * dt / T + 1e-9) << "phase " << p << " resets while visible at " << t;
      } else {
        EXPECT_NEAR(f1.tau_s[p] - f0.tau_s[p], dt, 1e-6);
      }
    }
  }
}

/// A small storm for the advection test: one round cell of cloud water (radius 5 columns, 9-km
/// columns, 500-m layers) centred on column (ci, cj), and a uniform wind when `wind` is non-zero.
ExtinctionVolumes advectionCell(int ci, int cj, glm::dvec2 wind, double clock_s) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(26, 26, 12, 9000.0, 500.0, 0.0);
  for (int k = 1; k < 10; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const double r = std::hypot(i - ci, 0.8 * (j - cj));
        if (r > 5.0) continue;
        const double top = 9.5 - 0.8 * r;  // a domed top
        if (k > top) continue;
        v.water_per_m[v.index(i, j, k)] = float(0.03 * std::exp(-0.5 * r * r / 6.0) * (k < 3 ? 0.5 : 1.0));
      }
  if (wind != glm::dvec2(0.0)) {
    v.wind_u_m_per_s.assign(v.voxelCount(), float(wind.x));
    v.wind_v_m_per_s.assign(v.voxelCount(), float(wind.y));
  }
  v.detail_clock_s = clock_s;
  v.updateMaxima();
  return v;
}

// Issue 13 "temporally coherent: the noise is fixed in the air mass — advected with the model wind":
// in closed form for a uniform wind u. At the clock where one phase alone is visible (φ = ½: phase
// a, τ = T/2; φ = 0: phase b, τ = T/2) the noise is read at x − u·T/2, so a cloud carried by the
// wind over u·T/2 (here exactly (1, −2) columns: u = (10, −20) m/s, T/2 = 900 s) with the advected
// noise is, point for point, the untranslated cloud with the world-fixed noise: the detail travels
// with the air. The same cloud with the world-fixed noise differs (the control: the noise did move).
TEST(Detail, AdvectedNoiseIsTheWorldFixedNoiseTranslatedByAUniformWind) {
  const double T = volume::kDetailFlowPeriod_s;
  const glm::dvec2 wind(10.0, -20.0);
  const glm::dvec3 shift_m(wind.x * 0.5 * T, wind.y * 0.5 * T, 0.0);  // (9 000, −18 000) m
  const ExtinctionVolumes here = advectionCell(12, 14, glm::dvec2(0.0), 0.0);
  const volume::VolumeFrame f = volume::frameOf(here, 8.0);
  const volume::ExtinctionSampler fixed(here, f, volume::Reconstruction::Trilinear, Detail::Full);
  ASSERT_EQ(fixed.detailFlow().weight_a, 1.0);
  ASSERT_EQ(fixed.detailFlow().tau_s, glm::dvec2(0.0));
  const double betaMax = double(here.max_water_per_m);
  for (const double phase : {0.5, 0.0}) {
    const ExtinctionVolumes there = advectionCell(13, 12, wind, (1000.0 + phase) * T);
    const volume::ExtinctionSampler advected(there, volume::frameOf(there, 8.0), volume::Reconstruction::Trilinear,
                                             Detail::Full);
    const ExtinctionVolumes thereCalm = advectionCell(13, 12, glm::dvec2(0.0), (1000.0 + phase) * T);
    const volume::ExtinctionSampler thereFixed(thereCalm, volume::frameOf(thereCalm, 8.0),
                                               volume::Reconstruction::Trilinear, Detail::Full);
    EXPECT_EQ(advected.detailFlow().weight_a, phase == 0.5 ? 1.0 : 0.0);
    double worst = 0.0, control = 0.0, cloudy = 0.0;
    int n = 0;
    for (double gz = 0.5; gz < 11.0; gz += 0.375)
      for (double gy = 7.0; gy < 21.0; gy += 0.3125)
        for (double gx = 5.0; gx < 19.0; gx += 0.3125) {
          const glm::dvec3 x = f.worldFromGrid({gx, gy, gz});  // multiples of 1/16 column: exact in float
          const double b0 = fixed.at(x).total(), b1 = advected.at(x + shift_m).total();
          worst = std::max(worst, std::abs(b1 - b0));
          control = std::max(control, std::abs(thereFixed.at(x + shift_m).total() - b0));
          cloudy = std::max(cloudy, b0);
          ++n;
        }
    std::printf("[ detail   ] phase %.1f: advected vs translated world-fixed max |Δβ| %.3g (β max %.3g), "
                "world-fixed vs translated %.3g, %d samples\n",
                phase, worst, betaMax, control, n);
    EXPECT_GT(cloudy, 0.2 * betaMax);  // the samples cover the cell
    // Float rounding of the positions only (x + shift − shift, the column index in float).
    EXPECT_LE(worst, 1e-4 * betaMax);
    EXPECT_GT(control, 0.05 * betaMax);
  }
}

// The advected field is continuous in time across a phase's reset (its weight is 0 there): over
// the one second of model time that ends at a reset, the detailed field moves no more than over an
// ordinary second a quarter period later (an unfaded reset would jump by the noise's whole contrast).
double largestChangeOverOneSecond(double clock_s) {
  const glm::dvec2 wind(10.0, -20.0);
  const ExtinctionVolumes before = advectionCell(12, 14, wind, clock_s - 1.0),
                          after = advectionCell(12, 14, wind, clock_s);
  const volume::VolumeFrame f = volume::frameOf(after, 8.0);
  const volume::ExtinctionSampler s0(before, f, volume::Reconstruction::Trilinear, Detail::Full),
      s1(after, f, volume::Reconstruction::Trilinear, Detail::Full);
  double worst = 0.0;
  for (double gz = 0.5; gz < 11.0; gz += 0.5)
    for (double gy = 7.0; gy < 21.0; gy += 0.4375)
      for (double gx = 5.0; gx < 19.0; gx += 0.4375) {
        const glm::dvec3 x = f.worldFromGrid({gx, gy, gz});
        worst = std::max(worst, std::abs(s1.at(x).total() - s0.at(x).total()));
      }
  return worst;
}

TEST(Detail, AdvectedFieldIsContinuousAcrossAPhaseReset) {
  const double T = volume::kDetailFlowPeriod_s;
  const double betaMax = double(advectionCell(12, 14, glm::dvec2(0.0), 0.0).max_water_per_m);
  const double reset = largestChangeOverOneSecond(1000.0 * T), ordinary = largestChangeOverOneSecond(1000.25 * T);
  std::printf("[ detail   ] over 1 s of model time: max |Δβ| %.3g ending at a reset, %.3g a quarter period later "
              "(β max %.3g)\n",
              reset, ordinary, betaMax);
  EXPECT_GT(ordinary, 0.0);  // the noise moves
  EXPECT_LE(reset, 2.0 * ordinary + 1e-3 * betaMax);
}

// ---- Level of detail: the noise read prefiltered to the ray's footprint (detail_field.glsl detailNoiseLod) ----

// The tile's mipmap chain (volume/noise.h noiseMipLevel, the GPU's too): every level is the box mean
// of the one before, so each channel keeps the tile's mean (up to the rounding of each level to a
// code: ≤ ½ code per level) while its spread falls level by level; lod ≤ 0 reads level 0 exactly
// (textureLod's magnification, as texture() before the level of detail), lod between two levels
// blends them continuously, and beyond the last level the tile is one colour.
TEST(Detail, NoiseMipChainKeepsTheTileMean) {
  const volume::NoiseVolume& n = volume::noiseVolume();
  ASSERT_EQ(n.mips.size(), std::size_t(volume::kNoiseLevels - 1));
  const auto moments = [](const std::vector<std::uint8_t>& rgba) {
    glm::dvec4 sum(0.0), sq(0.0);
    const std::size_t texels = rgba.size() / 4;
    for (std::size_t t = 0; t < texels; ++t) {
      const glm::dvec4 v = glm::dvec4(rgba[4 * t], rgba[4 * t + 1], rgba[4 * t + 2], rgba[4 * t + 3]) / 255.0;
      sum += v;
      sq += v * v;
    }
    const glm::dvec4 mean = sum / double(texels);
    return std::pair{mean, glm::sqrt(glm::max(sq / double(texels) - mean * mean, glm::dvec4(0.0)))};
  };
  const auto [mean0, sd0] = moments(n.rgba);
  glm::dvec4 sdPrev = sd0;
  for (int k = 1; k < volume::kNoiseLevels; ++k) {
    const std::vector<std::uint8_t>& level = n.mips[std::size_t(k - 1)];
    const int size = volume::kNoiseTexels >> k;
    ASSERT_EQ(level.size(), std::size_t(4) * std::size_t(size) * std::size_t(size) * std::size_t(size));
    const auto [mean, sd] = moments(level);
    std::printf(
        "[ detail   ] noise level %d (%d^3): mean r %.4f g %.4f b %.4f a %.4f, spread r %.4f g %.4f b %.4f a %.4f\n", k,
        size, mean.r, mean.g, mean.b, mean.a, sd.r, sd.g, sd.b, sd.a);
    for (int c = 0; c < 4; ++c) {
      EXPECT_LE(std::abs(mean[c] - mean0[c]), 0.5 * double(k) / 255.0) << "level " << k << " channel " << c;
      if (size >= 4) {
        EXPECT_LT(sd[c], sdPrev[c]) << "level " << k << " channel " << c;
      }
    }
    sdPrev = sd;
  }
  const glm::dvec4 last = n.sampleLod(glm::dvec3(0.0), double(volume::kNoiseLevels - 1));
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 q(0.37 * i - 3.1, 0.113 * i * i * 0.01 + 0.2, std::sin(0.7 * i) * 2.3);
    const glm::dvec4 t = n.sample(q);
    for (double lod : {-2.0, 0.0}) EXPECT_EQ(n.sampleLod(q, lod), t);
    for (double lod : {1.0, 2.0, 3.0, 4.0, 5.0}) {  // continuous across each level
      const glm::dvec4 d = n.sampleLod(q, lod - 1e-9) - n.sampleLod(q, lod + 1e-9);
      EXPECT_LE(glm::length(d), 1e-6) << "lod " << lod;
    }
    for (double lod : {6.0, 6.5, 40.0}) EXPECT_LE(glm::length(n.sampleLod(q, lod) - last), 1e-12);
  }
}

// The detailed field read through a footprint F (the eye pass passes its ray's width) against the
// full-resolution field, on the coarse storm with detail full: at 400 points in cloud, 32 points
// spread over a cube of side F around each. F = 4 texels of the tile (lod 2, ≈ 1.25 km here — a
// 1080p pixel at ~2 000 km, or ¼ of the demo's 960-pixel frame's pixel... the scale where the
// pictures' fringe crawled). Prefiltered, the field varies less inside its footprint — the grain
// that a single ray per pixel turns into crawling pixel noise — and keeps its mean: the density's
// and the shape's noise terms are centred, so the box mean moves the detailed field towards the
// mean of the detail, not away from the data's mass.
TEST(Detail, FootprintPrefiltersTheNoise) {
  const ExtinctionVolumes v = coarseStorm();
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  const volume::ExtinctionSampler s(v, f, volume::Reconstruction::Trilinear, Detail::Full);
  const double F = 4.0 * s.detail().period_m.x / double(volume::kNoiseTexels);
  std::vector<glm::dvec3> centres;
  for (int k = 0; k < v.nz && centres.size() < 400; ++k)
    for (int j = 0; j < v.ny && centres.size() < 400; j += 3)
      for (int i = 0; i < v.nx && centres.size() < 400; i += 3) {
        const glm::dvec3 p = f.worldFromGrid({i + 0.37, j + 0.61, k + 0.5});
        if (s.plainAt(p).total() > 1e-4) centres.push_back(p);
      }
  ASSERT_EQ(centres.size(), std::size_t(400));
  // Per centre, over its footprint: the spread of the detail's factor β_d / β (the noise's share of
  // the variation: β alone varies across 1.25 km too, most of all in height), and the mean of β_d.
  double spread0 = 0.0, spreadF = 0.0, mean0 = 0.0, meanF = 0.0;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    double s0 = 0.0, q0 = 0.0, sF = 0.0, qF = 0.0;
    int n = 0;
    constexpr int kOffsets = 32;
    for (int o = 0; o < kOffsets; ++o) {  // a fixed low-discrepancy spread over the cube (R3 sequence)
      const glm::dvec3 u = glm::fract(glm::dvec3(0.5) + double(o + 1) * glm::dvec3(0.8191725, 0.6710436, 0.5497005));
      const glm::dvec3 p = centres[c] + (u - 0.5) * F;
      const double b = s.plainAt(p).total(), b0 = s.at(p).total(), bF = s.at(p, F).total();
      mean0 += b0;
      meanF += bF;
      if (b < 1e-5) continue;
      s0 += b0 / b;
      q0 += (b0 / b) * (b0 / b);
      sF += bF / b;
      qF += (bF / b) * (bF / b);
      ++n;
    }
    if (n < 2) continue;
    spread0 += std::sqrt(std::max(q0 / n - (s0 / n) * (s0 / n), 0.0));
    spreadF += std::sqrt(std::max(qF / n - (sF / n) * (sF / n), 0.0));
  }
  std::printf("[ detail   ] footprint %.0f m (lod 2): spread of the detail's factor inside it %.3g -> %.3g (x%.2f); "
              "mean beta %.4g -> %.4g (%+.2f %%)\n",
              F, spread0 / double(centres.size()), spreadF / double(centres.size()), spreadF / spread0, mean0, meanF,
              100.0 * (meanF / mean0 - 1.0));
  EXPECT_LT(spreadF, 0.75 * spread0);
  EXPECT_LE(std::abs(meanF / mean0 - 1.0), 0.05);
  // Footprint 0 is the full-resolution field, bit for bit.
  for (std::size_t c = 0; c < 20; ++c) EXPECT_EQ(s.at(centres[c], 0.0).total(), s.at(centres[c]).total());
}

}  // namespace
}  // namespace nph::test
