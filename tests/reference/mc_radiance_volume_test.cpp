// The Monte Carlo radiance volume (reference/mc_radiance_volume.h; issue 12, fifteenth session)
// against closed forms and invariants.
#include "reference/mc_radiance_volume.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "reference/path_tracer_field.h"
#include "volume/volume_frame.h"

namespace nph::reference {
namespace {

ExtinctionVolumes homogeneousBox(int nx, int ny, int nz, double dx_m, double dz_m, float water_per_m,
                                 float ice_per_m = 0.0f) {
  ExtinctionVolumes v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.dz_m = dz_m;
  v.georef.dx_m = dx_m;
  v.georef.dy_m = dx_m;
  const std::size_t n = std::size_t(nx) * std::size_t(ny) * std::size_t(nz);
  v.water_per_m.assign(n, water_per_m);
  v.ice_per_m.assign(n, ice_per_m);
  v.max_water_per_m = water_per_m;
  v.max_ice_per_m = ice_per_m;
  return v;
}

// The direct beam's fluence (order 0 only) is E·e^{−τ(x)}, τ the exact optical depth to the sun
// (path_tracer_field.h). Height × 4 and an oblique sun: the photons must fly with β scaled by
// opticalDepthScale exactly as the path tracer's, or the beam's depth is wrong by up to × 4; the
// power per photon (projected area of the sun-facing faces / N) and the track-length tally's
// normalisation (per world cell volume) must be right, or every cell is off by the same factor.
TEST(McRadianceVolume, DirectBeamFluenceIsTheExactTransmittance) {
  const ExtinctionVolumes v = homogeneousBox(24, 24, 12, 100.0, 50.0, 0.004f);
  const volume::VolumeFrame frame = volume::frameOf(v, 4.0);
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(0.6, 0.2, 0.5));
  McTallySpec beam;
  beam.min_order = 0;
  beam.max_order = 0;
  McSettings s;
  s.photons = 1000000;
  const McRadianceVolume mc = traceMcRadianceVolumes(v, frame, toSun, {beam}, s).front();
  ASSERT_EQ(mc.cells, glm::ivec3(6, 6, 6));
  const ExtinctionField field(v, frame);
  double worst = 0.0, mean = 0.0;
  int checked = 0;
  for (int k = 0; k < mc.cells.z; ++k)
    for (int j = 0; j < mc.cells.y; ++j)
      for (int i = 0; i < mc.cells.x; ++i) {
        // The cell's mean of e^{−τ}, m³ midpoint nodes (τ has kinks where the sun's path leaves
        // through another face: 4³ nodes are off by up to 4 %, 10³ by < 1 %).
        constexpr int m = 10;
        double expected = 0.0;
        for (int q = 0; q < m * m * m; ++q) {
          const glm::dvec3 f((q % m + 0.5) / m, (q / m % m + 0.5) / m, (q / (m * m) + 0.5) / m);
          const glm::dvec3 x = frame.min_m() + (glm::dvec3(i, j, k) + f) * mc.cell_m;
          expected += std::exp(-field.opticalDepth(x, toSun, 0.0, 1e30)) / double(m * m * m);
        }
        const double got = mc.moment(mc.index(i, j, k), 0) * 2.0 * std::sqrt(std::numbers::pi);
        if (expected < 0.1) continue;
        ++checked;
        worst = std::max(worst, std::abs(got / expected - 1.0));
        mean += got / expected - 1.0;
      }
  ASSERT_GT(checked, 80);
  // 10⁶ photons: the cells' relative RMS error is 1.4 %, the worst of 91 cells 5 % (seed 15);
  // the mean over the cells tests the normalisation (+0.5 %).
  EXPECT_LT(worst, 0.08) << "worst relative error of the beam's cell fluence";
  EXPECT_LT(std::abs(mean / checked), 0.015) << "mean relative error of the beam's cell fluence";
  // The beam's flux points away from the sun with |F| = φ (a delta in direction).
  const std::size_t c = mc.index(3, 3, 4);
  const glm::dvec3 flux =
      glm::dvec3(mc.moment(c, 3), mc.moment(c, 1), mc.moment(c, 2)) * std::sqrt(4.0 * std::numbers::pi / 3.0);
  const double phi = mc.moment(c, 0) * 2.0 * std::sqrt(std::numbers::pi);
  EXPECT_NEAR(glm::dot(flux, -toSun) / phi, 1.0, 1e-9);
}

// A conservative slab lit from straight above: energy is conserved, so the net vertical flux of all
// light (beam and every order) is the same at every depth (∂F_z/∂z = 0 in 1-D), and it is the
// transmitted share −(1 − R)·E. In the middle of a slab 16 times as wide as it is thick the sides
// do not matter. R from the δ-Eddington closed form (Joseph, Wiscombe & Weinman 1976, conservative
// case, μ₀ = 1): 0.240 for τ = 5, g = 0.85. δ-Eddington's error for conservative slabs is a few
// per cent of the flux (King & Harshvardhan 1986); the tally gives T = 0.761 against 0.760.
double deltaEddingtonReflectance(double tau, double g, double mu0) {
  const double f = g * g, gs = g / (1.0 + g), k = 1.0 - gs, tt = (1.0 - f) * tau;
  const double F = 1.0 / std::numbers::pi, et = std::exp(-tt / mu0);
  const double c1 = (0.75 * F * mu0 * mu0 * (et - 1.0) - 0.5 * F * mu0 * (et + 1.0)) / (k * tt + 4.0 / 3.0);
  const double c2 = 0.75 * F * mu0 * (mu0 + 2.0 / 3.0) + 2.0 / 3.0 * c1;
  const double i0 = c2 - 0.75 * F * mu0 * mu0, i1 = 0.75 * F * mu0 + c1;  // at the top
  return std::numbers::pi * (i0 + 2.0 / 3.0 * i1) / mu0;                  // F↑ = π(I₀ + ⅔I₁)
}

TEST(McRadianceVolume, ConservativeSlabCarriesTheSameNetFluxAtEveryDepth) {
  const ExtinctionVolumes v = homogeneousBox(32, 32, 8, 100.0, 25.0, 0.025f);  // τ = 5, 3.2 km × 200 m
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  McTallySpec all;
  all.min_order = 0;
  all.coarsen_xy = 8;
  all.coarsen_z = 1;
  McSettings s;
  s.photons = 120000;
  McStats stats;
  const McRadianceVolume mc = traceMcRadianceVolumes(v, frame, glm::dvec3(0, 0, 1), {all}, s, &stats).front();
  ASSERT_EQ(mc.cells, glm::ivec3(4, 4, 8));
  const double r = deltaEddingtonReflectance(5.0, 0.85, 1.0);
  EXPECT_NEAR(r, 0.240, 1e-3);
  // The whole top face reflects less: light near the sides leaks out sideways.
  EXPECT_LT(stats.escaped_up, r);
  EXPECT_GT(stats.escaped_up, 0.75 * r);
  const double norm = std::sqrt(4.0 * std::numbers::pi / 3.0);
  double lo = 0.0, hi = -1.0;
  for (int k = 0; k < mc.cells.z; ++k) {
    double fz = 0.0;  // the central 2 × 2 columns
    for (int j = 1; j <= 2; ++j)
      for (int i = 1; i <= 2; ++i) fz += 0.25 * mc.moment(mc.index(i, j, k), 2) * norm;
    EXPECT_NEAR(fz, -(1.0 - r), 0.02) << "layer " << k;
    lo = std::min(lo, fz);
    hi = std::max(hi, fz);
  }
  EXPECT_LT(hi - lo, 0.01) << "the net flux changes with depth (measured 0.005 at 1.2·10⁵ photons)";
}

// The same seed gives the same volume bit for bit whatever the thread count; another seed does not.
TEST(McRadianceVolume, SameSeedSameVolumeBitForBit) {
  ExtinctionVolumes v = homogeneousBox(16, 16, 8, 200.0, 100.0, 0.01f, 0.002f);
  for (std::size_t i = 0; i < v.water_per_m.size(); i += 7) v.water_per_m[i] = 0.0f;  // some structure
  const volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(-0.3, 0.5, 0.4));
  McSettings s;
  s.photons = 3000;
  s.threads = 1;
  const std::vector<McTallySpec> specs{McTallySpec{}, McTallySpec{2, 1, 2, -1, 3}};
  const auto a = traceMcRadianceVolumes(v, frame, toSun, specs, s);
  s.threads = 2;
  const auto b = traceMcRadianceVolumes(v, frame, toSun, specs, s);
  s.seed = 16;
  const auto c = traceMcRadianceVolumes(v, frame, toSun, specs, s);
  ASSERT_EQ(a.size(), 2u);
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].moments, b[t].moments);
    EXPECT_NE(a[t].moments, c[t].moments);
  }
  double sum = 0.0;
  for (std::size_t cell = 0; cell < a[0].moments.size() / std::size_t(a[0].harmonics()); ++cell)
    sum += a[0].moment(cell, 0);
  EXPECT_GT(sum, 0.0);
}

// The source function's series: an isotropic field scatters φ/(4π) whatever g; a beam (a delta in
// direction d) scatters Σ_{l ≤ L} (2l + 1)/(4π)·g^l·P_l(d·ω), the HG phase function's Legendre
// series — which checks the harmonics by the addition theorem, order by order.
TEST(McRadianceVolume, SourceFunctionIsTheTruncatedPhaseSeries) {
  McMoments iso{};
  iso[0] = 2.0 * std::sqrt(std::numbers::pi);  // L = 1 everywhere: c00 = ∫ Y00 dω = √(4π)
  const glm::dvec3 w = glm::normalize(glm::dvec3(0.3, -0.4, 0.8));
  const double g = 0.75;
  std::array<double, kMcMaxL + 1> G{};
  for (int l = 0; l <= kMcMaxL; ++l) G[std::size_t(l)] = std::pow(g, l);
  EXPECT_NEAR(harmonicSourceFunction(iso, w, G, kMcMaxL), 1.0, 1e-12);  // J = L = 1
  for (const glm::dvec3& dd : {glm::dvec3(-0.5, 0.2, -0.7), glm::dvec3(0.1, 0.9, 0.3), glm::dvec3(0.3, -0.4, 0.8),
                               glm::dvec3(0.0, 0.0, -1.0), glm::dvec3(-0.6, -0.8, 0.0)}) {
    const glm::dvec3 d = glm::normalize(dd);
    const McMoments beam = sphericalHarmonics(d);  // c_lm = Y_lm(d) for a unit delta
    const double mu = glm::dot(d, w);
    double pPrev = 1.0, p = mu;  // Legendre P_l(μ) by Bonnet's recurrence
    double expected = 0.0;
    for (int l = 0; l <= kMcMaxL; ++l) {
      const double pl = l == 0 ? 1.0 : p;
      expected += (2.0 * l + 1.0) / (4.0 * std::numbers::pi) * G[std::size_t(l)] * pl;
      EXPECT_NEAR(harmonicSourceFunction(beam, w, G, l), expected, 1e-11) << "l " << l;
      if (l >= 1) {
        const double next = ((2.0 * l + 1.0) * mu * p - double(l) * pPrev) / double(l + 1);
        pPrev = p;
        p = next;
      }
    }
  }
  // The first harmonics are the closed forms (Sloan 2008, without the Condon–Shortley sign).
  const glm::dvec3 d = glm::normalize(glm::dvec3(0.2, -0.5, 0.6));
  const McMoments y = sphericalHarmonics(d);
  EXPECT_NEAR(y[0], 0.28209479177387814, 1e-15);
  EXPECT_NEAR(y[2], 0.4886025119029199 * d.z, 1e-15);
  EXPECT_NEAR(y[6], 0.31539156525252005 * (3.0 * d.z * d.z - 1.0), 1e-15);
  EXPECT_NEAR(y[8], 0.5462742152960396 * (d.x * d.x - d.y * d.y), 1e-15);
}

TEST(McRadianceVolume, BadInputIsAClearError) {
  const ExtinctionVolumes v = homogeneousBox(4, 4, 4, 100.0, 100.0, 0.01f);
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  EXPECT_ANY_THROW(traceMcRadianceVolumes(v, frame, glm::dvec3(0, 0, 1), {}, McSettings{}));
  McSettings zero;
  zero.photons = 0;
  EXPECT_ANY_THROW(traceMcRadianceVolumes(v, frame, glm::dvec3(0, 0, 1), {McTallySpec{}}, zero));
  EXPECT_ANY_THROW(traceMcRadianceVolumes(v, frame, glm::dvec3(0.0), {McTallySpec{}}, McSettings{}));
}

}  // namespace
}  // namespace nph::reference
