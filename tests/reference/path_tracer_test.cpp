// Verification of the Monte Carlo path tracer (src/reference/path_tracer.h) on its own:
// alpha against Beer–Lambert (slab, sphere), the majorant grid as a bound, single scattering of a
// slab against its closed form, the optically thin limit of full multiple scattering, the white
// furnace, error ∝ N^-1/2, a ground-only scene with a closed form, and determinism across seeds and
// thread counts. Every statistical assertion compares with the estimator's own standard error.
#include "reference/path_tracer.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "reference/path_tracer_sampling.h"
#include "volume/volume_frame.h"

namespace nph::reference {
namespace {

constexpr double kPi = std::numbers::pi;

ExtinctionVolumes emptyVolume(int nx, int ny, int nz, double dx_m, double dz_m, double z_bottom_m) {
  return ExtinctionVolumes::zeros(nx, ny, nz, dx_m, dz_m, z_bottom_m);
}

// Homogeneous water slab: 100 km × 100 km, 1 km thick from 1 km to 2 km height.
struct Slab {
  ExtinctionVolumes volumes;
  double sigma_per_m = 0.0;  // the float value actually stored
  static constexpr double kThickness_m = 1000.0;
  static constexpr double kBottom_m = 1000.0;
  explicit Slab(double tau) : volumes(emptyVolume(4, 4, 2, 25000.0, 500.0, kBottom_m)) {
    const float s = float(tau / kThickness_m);
    volumes.water_per_m.assign(volumes.voxelCount(), s);
    volumes.updateMaxima();
    sigma_per_m = double(s);
  }
};

// Single scattering of a plane-parallel slab seen from above, sun above (e.g. Liou 2002 §6.2):
//   L₁ = E p(cos ψ) μ_s/(μ_s + μ_v) (1 − exp(−τ (1/μ_s + 1/μ_v))).
double slabSingleScattering(double tau, double irradiance, double phase, double mu_s, double mu_v) {
  return irradiance * phase * mu_s / (mu_s + mu_v) * (1.0 - std::exp(-tau * (1.0 / mu_s + 1.0 / mu_v)));
}

struct SlabView {
  glm::dvec3 origin{50000.0, 50000.0, 3000.0};
  glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, 0.5, -1.0));
  scene::Sun sun;
  SlabView() {
    sun.azimuth_deg = 200.0;
    sun.elevation_deg = 50.0;
    sun.intensity = 2.0;
    sun.colour = {1.0, 0.8, 0.6};
  }
  double exact(const Slab& slab, const physics::PhaseFunction& phase) const {
    const glm::dvec3 toSun = sun.toSun();
    return slabSingleScattering(slab.sigma_per_m * Slab::kThickness_m, sun.intensity, phase.eval(glm::dot(toSun, dir)),
                                toSun.z, -dir.z);
  }
};

// Diffuse flux through the horizontal plane at height z (world metres, above the slab centre):
// π × the mean radiance over n cosine-distributed directions looking towards −sign·z (sign = −1
// looks down: the upward flux). `se` receives its standard error; `stats` (optional) sums the
// paths' counters.
double diffuseFlux(const PathTracer& pt, double z, double sign, int n, std::uint64_t stream0, double& se,
                   PathTracerStats* stats) {
  std::mt19937_64 rng(stream0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double sum = 0.0, sumSq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double cosTheta = std::sqrt(u(rng)), phi = 2.0 * kPi * u(rng);
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    const glm::dvec3 d(sinTheta * std::cos(phi), sinTheta * std::sin(phi), sign * cosTheta);
    const PixelEstimate e = pt.estimateRay({50000.0, 50000.0, z}, d, 1, stream0 + std::uint64_t(i));
    sum += e.rgb.x;
    sumSq += e.rgb.x * e.rgb.x;
    if (stats) {
      stats->truncated_paths += e.stats.truncated_paths;
      stats->rouletted_paths += e.stats.rouletted_paths;
      stats->medium_collisions += e.stats.medium_collisions;
      stats->max_path_weight = std::max(stats->max_path_weight, e.stats.max_path_weight);
    }
  }
  const double mean = sum / n;
  se = kPi * std::sqrt((sumSq / n - mean * mean) / (n - 1));
  return kPi * mean;
}

PathTracerSettings sunOnly(int max_events) {
  PathTracerSettings s;
  s.max_events = max_events;
  s.sky_radiance = glm::dvec3(0.0);
  return s;
}

TEST(PathTracer, DirectionsAroundAnAxisHaveTheRequestedAngleAndUniformAzimuth) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> axes{{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  for (int i = 0; i < 20; ++i) axes.push_back(glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)));
  for (const glm::dvec3& axis : axes) {
    const double mu = 2.0 * u(rng) - 1.0;
    glm::dvec3 mean{0.0};
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 d = aroundAxis(axis, mu, 2.0 * kPi * u(rng));
      ASSERT_NEAR(glm::length(d), 1.0, 1e-12);
      ASSERT_NEAR(glm::dot(d, axis), mu, 1e-12);
      mean += d / double(n);
    }
    // Uniform azimuth: the perpendicular part averages out (s.d. of the mean ≈ 0.7/√n).
    EXPECT_NEAR(glm::length(mean - mu * axis), 0.0, 5.0 * 0.71 / std::sqrt(double(n)));
  }
}

TEST(PathTracer, AlphaOfHomogeneousSlabIsBeerLambert) {
  const Slab slab(0.7);
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), scene::Sun{}, sunOnly(1));
  for (const glm::dvec3 d : {glm::dvec3(0, 0, -1), glm::dvec3(0.3, 0.5, -1), glm::dvec3(-2, 1, -0.4)}) {
    const glm::dvec3 dir = glm::normalize(d);
    const double expected = 1.0 - std::exp(-slab.sigma_per_m * Slab::kThickness_m / -dir.z);
    EXPECT_NEAR(pt.alpha({50000.0, 50000.0, 3000.0}, dir), expected, 1e-12) << dir.x << " " << dir.z;
  }
  // A ray through both side faces at mid-height: β ramps linearly from 0 to σ between ½ voxel
  // outside and ½ voxel inside each face (the GPU's zero border), which integrates to the same τ
  // as the box chord: σ × 100 km.
  const glm::dvec3 o{-30000.0, 50000.0, 1500.0};
  EXPECT_NEAR(pt.alpha(o, {1.0, 0.0, 0.0}), 1.0 - std::exp(-slab.sigma_per_m * 100000.0), 1e-12);
  // Starting on the face: the outer half of the first ramp (0 → ½σ over ½ voxel: σ·⅛ voxel) is
  // behind the origin.
  EXPECT_NEAR(pt.alpha({0.0, 50000.0, 1500.0}, {1.0, 0.0, 0.0}),
              1.0 - std::exp(-slab.sigma_per_m * (100000.0 - 0.125 * 25000.0)), 1e-12);
  // The zero-border rule of volume/extinction_sampler.h: ½σ on the face, 0 half a voxel out.
  const ExtinctionField& f = pt.field();
  EXPECT_NEAR(f.at({0.0, 50000.0, 1500.0}).total(), 0.5 * slab.sigma_per_m, 1e-15);
  EXPECT_NEAR(f.at({50000.0, 50000.0, 2125.0}).total(), 0.25 * slab.sigma_per_m, 1e-15);
  EXPECT_EQ(f.at({-12500.0, 50000.0, 1500.0}).total(), 0.0);
  EXPECT_EQ(f.at({50000.0, 50000.0, 2250.0}).total(), 0.0);
  // A ray that misses the box, and the ground plane cutting the slab's column short.
  EXPECT_EQ(pt.alpha({50000.0, 50000.0, 3000.0}, {0.0, 0.0, 1.0}), 0.0);
  PathTracerSettings s = sunOnly(1);
  s.ground_enabled = true;
  s.ground_height_m = 1600.0;
  const PathTracer withGround(slab.volumes, volume::frameOf(slab.volumes), scene::Sun{}, s);
  EXPECT_NEAR(withGround.alpha({50000.0, 50000.0, 3000.0}, {0.0, 0.0, -1.0}), 1.0 - std::exp(-slab.sigma_per_m * 400.0),
              1e-12);
}

TEST(PathTracer, AlphaOfSphereIsBeerLambertWithinVoxelisation) {
  // Ball of radius R in a 48³ grid of 100 m voxels, voxel value = σ × covered fraction (4³
  // supersampling). The voxelised ball differs from the true one only within ~½ voxel of the
  // surface, so τ along a chord may differ from σ·2√(R² − b²) by about σ × ½ voxel per crossing.
  const int n = 48;
  const double h = 100.0, radius = 2000.0, sigma = 5e-4;
  ExtinctionVolumes v = emptyVolume(n, n, n, h, h, 0.0);
  const glm::dvec3 centre(n * h / 2.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        int inside = 0;
        for (int s = 0; s < 64; ++s) {
          const glm::dvec3 p = (glm::dvec3(i, j, k) + (glm::dvec3(s % 4, (s / 4) % 4, s / 16) + 0.5) / 4.0) * h;
          inside += glm::length(p - centre) < radius ? 1 : 0;
        }
        v.ice_per_m[v.index(i, j, k)] = float(sigma * inside / 64.0);
      }
  v.updateMaxima();
  const PathTracer pt(v, volume::frameOf(v), scene::Sun{}, sunOnly(1));
  for (double b : {0.0, 500.0, 1000.0, 1500.0, 1800.0}) {
    const glm::dvec3 o = centre + glm::dvec3(b, -5000.0, 0.0);
    const double tau = -std::log1p(-pt.alpha(o, {0.0, 1.0, 0.0}));
    const double expected = sigma * 2.0 * std::sqrt(radius * radius - b * b);
    EXPECT_NEAR(tau, expected, sigma * 0.5 * h) << "impact parameter " << b;
    // Oblique chord through the same ball.
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.6, 0.7, 0.3));
    const glm::dvec3 side = glm::normalize(glm::cross(dir, glm::dvec3(0, 0, 1)));
    const double tau2 = -std::log1p(-pt.alpha(centre + b * side - 4000.0 * dir, dir));
    EXPECT_NEAR(tau2, expected, sigma * 0.5 * h) << "oblique, impact parameter " << b;
  }
}

TEST(PathTracer, MajorantGridBoundsTheFieldAndTraversalCoversTheRay) {
  // Random field (lognormal-ish with empty regions), odd sizes so the last bricks are partial.
  ExtinctionVolumes v = emptyVolume(21, 13, 10, 300.0, 150.0, 500.0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < v.voxelCount(); ++i) {
    if (u(rng) < 0.3) continue;
    v.ice_per_m[i] = float(1e-3 * std::exp(4.0 * u(rng) - 2.0));
    v.water_per_m[i] = float(u(rng) < 0.5 ? 0.0 : 2e-3 * u(rng));
  }
  const volume::VolumeFrame frame = volume::frameOf(v);
  // Both filters (volume/reconstruction.h): the cubic B-spline reads 2 voxels past a brick.
  for (const auto& [brick, rec] : {std::pair{1, volume::Reconstruction::Trilinear},
                                   {4, volume::Reconstruction::Trilinear},
                                   {8, volume::Reconstruction::Trilinear},
                                   {1, volume::Reconstruction::Cubic},
                                   {4, volume::Reconstruction::Cubic},
                                   {8, volume::Reconstruction::Cubic},
                                   {4, volume::Reconstruction::CubicInterpolating}}) {
    SCOPED_TRACE(std::string(volume::kReconstructionNames[std::size_t(rec)]));
    const ExtinctionField field(v, frame, rec);
    const MajorantGrid grid(field, brick);
    const glm::dvec3 lo = field.supportMin(), size = field.supportMax() - field.supportMin();
    for (int i = 0; i < 20000; ++i) {
      const glm::dvec3 p = lo + glm::dvec3(u(rng), u(rng), u(rng)) * size;  // incl. the zero-border rim
      ASSERT_LE(field.at(p).total(), grid.majorantAt(p)) << "brick " << brick;
    }
    for (int r = 0; r < 300; ++r) {
      const glm::dvec3 o = lo + glm::dvec3(u(rng), u(rng), u(rng)) * size;
      const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
      double t0 = 0.0, t1 = 0.0;
      ASSERT_TRUE(field.clipToBox(o, d, 0.0, 1e9, t0, t1));
      double covered = 0.0, last = t0;
      grid.traverse(o, d, 0.0, 1e9, [&](double mu, double ta, double tb) {
        EXPECT_NEAR(ta, last, 1e-6);
        last = tb;
        covered += tb - ta;
        for (int s = 0; s < 4; ++s) {
          EXPECT_LE(field.at(o + (ta + u(rng) * (tb - ta)) * d).total(), mu);
        }
        return true;
      });
      EXPECT_NEAR(covered, t1 - t0, 1e-6 * (t1 - t0) + 1e-9);
    }
  }
  v.water_per_m[17] = std::nanf("");
  const ExtinctionField bad(v, frame);
  EXPECT_THROW(MajorantGrid{bad}, InputError);
}

TEST(PathTracer, OpticalDepthIsExactForTheTrilinearAndCubicFields) {
  // Random heterogeneous field: the piecewise Gauss–Legendre τ (2 nodes trilinear, 5 nodes cubic)
  // against a brute-force midpoint rule with 2·10⁵ points per ray (its error, from the kinks at
  // voxel-centre planes, is ~1e-9; the cubic field is C², smoother still).
  ExtinctionVolumes v = emptyVolume(11, 7, 5, 300.0, 150.0, 500.0);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < v.voxelCount(); ++i) {
    v.ice_per_m[i] = float(1e-3 * u(rng));
    v.water_per_m[i] = float(u(rng) < 0.5 ? 0.0 : 3e-3 * u(rng));
  }
  const volume::VolumeFrame frame = volume::frameOf(v);
  for (const volume::Reconstruction rec : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    SCOPED_TRACE(std::string(volume::kReconstructionNames[std::size_t(rec)]));
    const ExtinctionField field(v, frame, rec);
    for (int r = 0; r < 40; ++r) {
      // Origins inside the box, in the half-voxel rim around it (β fading to the zero border) and
      // outside; the brute force spans the whole support.
      const glm::dvec3 o =
          frame.min_m() + glm::dvec3(1.4 * u(rng) - 0.2, 1.4 * u(rng) - 0.2, 1.4 * u(rng) - 0.2) * frame.size_m();
      glm::dvec3 d = glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
      if (r % 10 == 0) d = glm::dvec3(0.0, 0.0, r % 20 == 0 ? 1.0 : -1.0);  // along a grid axis
      double t0 = 0.0, t1 = 0.0;
      if (!field.clipToBox(o, d, 0.0, 1e9, t0, t1)) {
        EXPECT_EQ(field.opticalDepth(o, d, 0.0, 1e9), 0.0);
        continue;
      }
      const int n = 200000;
      double brute = 0.0;
      for (int i = 0; i < n; ++i) brute += field.at(o + (t0 + (i + 0.5) * (t1 - t0) / n) * d).total();
      brute *= (t1 - t0) / n;
      EXPECT_NEAR(field.opticalDepth(o, d, 0.0, 1e9), brute, 1e-7 * brute + 1e-12) << "ray " << r;
    }
  }
}

// The cubic B-spline (volume/reconstruction.h) reproduces constant and linear fields away from the
// border (its weights sum to 1 and have their centroid at the sample), never leaves the range of
// the voxels it reads, is smoother than trilinear across a voxel-centre plane (no kink), and
// reaches exactly 1½ voxels past the box.
TEST(PathTracer, CubicBSplineReproducesLinearFieldsAndReachesOneAndAHalfVoxels) {
  ExtinctionVolumes v = emptyVolume(12, 10, 8, 1000.0, 250.0, 0.0);
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        v.water_per_m[v.index(i, j, k)] = float(1e-3 + 1e-4 * i + 2e-4 * j + 3e-4 * k);  // linear in the centres
        v.ice_per_m[v.index(i, j, k)] = 2e-3f;
      }
  const volume::VolumeFrame frame = volume::frameOf(v);
  const ExtinctionField cubic(v, frame, volume::Reconstruction::Cubic);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    // ≥ 2 voxels from every face: no zero-border voxel takes part.
    const glm::dvec3 g(2.0 + 8.0 * u(rng), 2.0 + 6.0 * u(rng), 2.0 + 4.0 * u(rng));
    const Extinction e = cubic.at(frame.worldFromGrid(g));
    // (up to the float rounding of the stored voxels, ~3e-10 here)
    EXPECT_NEAR(e.ice_per_m, 2e-3, 1e-9);
    EXPECT_NEAR(e.water_per_m, 1e-3 + 1e-4 * (g.x - 0.5) + 2e-4 * (g.y - 0.5) + 3e-4 * (g.z - 0.5), 1e-9);
  }
  // Support: β > 0 up to 1½ voxels outside a face, 0 beyond (and the support box says so).
  const double yMid = 5.0, zMid = 4.0;
  EXPECT_GT(cubic.at(frame.worldFromGrid({-1.49, yMid, zMid})).total(), 0.0);
  EXPECT_EQ(cubic.at(frame.worldFromGrid({-1.51, yMid, zMid})).total(), 0.0);
  EXPECT_NEAR(cubic.supportMin().x, -1.5 * frame.voxel_size_m.x, 1e-9);
  // A single voxel: the B-spline's peak is (2/3)³ of the voxel at its centre, the trilinear's 1.
  ExtinctionVolumes one = emptyVolume(5, 5, 5, 1000.0, 1000.0, 0.0);
  one.water_per_m[one.index(2, 2, 2)] = 1e-3f;
  const volume::VolumeFrame f1 = volume::frameOf(one);
  const glm::dvec3 centre = f1.worldFromGrid({2.5, 2.5, 2.5});
  const double stored = double(1e-3f);
  EXPECT_NEAR(ExtinctionField(one, f1, volume::Reconstruction::Cubic).at(centre).total(), stored * 8.0 / 27.0, 1e-15);
  EXPECT_NEAR(ExtinctionField(one, f1).at(centre).total(), stored, 1e-15);
  // Its optical mass ∫β dV is the voxel's, as for trilinear: τ of vertical rays integrated over x, y
  // by the midpoint rule on a fine grid of rays (exact up to the rule's ~1e-5 relative error).
  for (const volume::Reconstruction rec : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    const ExtinctionField field(one, f1, rec);
    const int n = 120;
    const double lo = 0.0, hi = 5.0;  // grid units: the whole support (1.5 … 3.5 voxels for cubic)
    double mass = 0.0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const glm::dvec3 top = f1.worldFromGrid({lo + (a + 0.5) * (hi - lo) / n, lo + (b + 0.5) * (hi - lo) / n, 7.0});
        mass += field.opticalDepth(top, {0.0, 0.0, -1.0}, 0.0, 1e9);
      }
    mass *= std::pow((hi - lo) / n * 1000.0, 2.0);
    EXPECT_NEAR(mass, stored * 1e9, 1e-4 * 1e6) << volume::kReconstructionNames[std::size_t(rec)];
  }
}

TEST(PathTracer, SingleScatteringOfSlabMatchesClosedForm) {
  const Slab slab(0.5);
  const SlabView view;
  for (SunTransmittance tr : {SunTransmittance::RatioTracking, SunTransmittance::Exact}) {
    PathTracerSettings s = sunOnly(1);
    s.sun_transmittance = tr;
    const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), view.sun, s);
    const PixelEstimate e = pt.estimateRay(view.origin, view.dir, 200000, 11);
    const double exact = view.exact(slab, s.phase.water);
    for (int c = 0; c < 3; ++c) {
      const double expected = exact * view.sun.colour[c];
      EXPECT_LT(e.standard_error[c], 0.01 * expected);
      EXPECT_NEAR(e.rgb[c], expected, 4.0 * e.standard_error[c]) << "channel " << c;
    }
    EXPECT_EQ(e.stats.truncated_paths, e.stats.medium_collisions);  // every collided path ends there
  }
}

TEST(PathTracer, SingleScatteringOfMixedSlabUsesNesEq512) {
  // Same slab, a quarter ice (Cornette–Shanks g = 0.9) and three quarters water (HG 0.85): the
  // single-scattered radiance takes the β_sca-weighted mean phase P_v of Nes eq. 5.12.
  Slab slab(0.5);
  for (std::size_t i = 0; i < slab.volumes.voxelCount(); ++i) {
    slab.volumes.ice_per_m[i] = float(0.25 * slab.sigma_per_m);
    slab.volumes.water_per_m[i] = float(0.75 * slab.sigma_per_m);
  }
  const SlabView view;
  PathTracerSettings s = sunOnly(1);
  s.phase.ice = physics::PhaseFunction::transportDefault();
  s.sun_transmittance = SunTransmittance::Exact;
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), view.sun, s);
  const PixelEstimate e = pt.estimateRay(view.origin, view.dir, 200000, 5);
  const double cosPsi = glm::dot(view.sun.toSun(), view.dir);
  const double mixed = s.phase.eval(cosPsi, 0.25, 0.75);
  EXPECT_GT(std::abs(s.phase.ice.eval(cosPsi) / s.phase.water.eval(cosPsi) - 1.0), 0.2);  // distinguishable
  const double exact = view.exact(slab, s.phase.water) * mixed / s.phase.water.eval(cosPsi);
  EXPECT_LT(e.standard_error.x, 0.01 * exact);
  EXPECT_NEAR(e.rgb.x, exact, 4.0 * e.standard_error.x);
}

TEST(PathTracer, SunlitSlabConservesEnergy) {
  // Albedo 1: the sunlight a slab of optical depth τ intercepts, E μ_s (1 − e^{−τ/μ_s}), leaves it
  // as diffuse flux up or down. Each flux is π × the mean radiance over cosine-distributed view
  // directions, measured 1 m above the top and 1 m below the bottom (far from the side faces).
  // Multiple scattering, phase sampling, NEE and ratio tracking all enter this balance.
  const Slab slab(2.0);
  const SlabView view;
  PathTracerSettings s = sunOnly(100000);
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), view.sun, s);
  const int n = 150000;
  auto flux = [&](double z, double sign, std::uint64_t stream0, double& se) {
    return diffuseFlux(pt, z, sign, n, stream0, se, nullptr);
  };
  double seUp = 0.0, seDown = 0.0;
  const double up = flux(Slab::kBottom_m + Slab::kThickness_m + 1.0, -1.0, 1u << 20, seUp);
  const double down = flux(Slab::kBottom_m - 1.0, 1.0, 1u << 21, seDown);
  const double muS = view.sun.toSun().z;
  const double intercepted = view.sun.intensity * muS * (1.0 - std::exp(-slab.sigma_per_m * Slab::kThickness_m / muS));
  const double se = std::sqrt(seUp * seUp + seDown * seDown);
  std::printf("sunlit slab: up %.4f down %.4f sum %.4f vs intercepted %.4f (s.e. %.4f)\n", up, down, up + down,
              intercepted, se);
  EXPECT_LT(se, 0.012 * intercepted);
  EXPECT_NEAR(up + down, intercepted, 4.0 * se);
}

TEST(PathTracer, ThickSlabTransmissionMatchesVanDeHulstUnderRoulette) {
  // A thick conservative slab, isotropic scattering, sun at the zenith (μ₀ = 1): the asymptotic
  // theory of thick layers (van de Hulst 1980, "Multiple Light Scattering" vol. 2, ch. 14; for
  // conservative scattering exact up to terms exponentially small in τ) gives the diffuse flux
  // transmission T(μ₀) = 4 K(μ₀) / (3 (τ + 2 q₀)), with q₀ = 0.710446 (Hopf's constant) and the
  // escape function K(μ) = (√3/4)·H(μ) (normalised 2∫K μ dμ = 1), H(1) = 2.90781 (Chandrasekhar
  // 1960, table XI, ϖ = 1). At τ = 20: T = 0.07837, R = 1 − T. Russian roulette is set to start
  // after 128 collisions (transmitted paths take O(τ²) ≈ 400), so the balance also shows that the
  // roulette is unbiased; no path may reach the hard cap. (Starting it after 16 collisions: the
  // next test.) Measured: T = 0.0765 ± 0.0016 (−2.5 %, 1.2 s.e.), R + T = 1.000 ± 0.003, 8 390
  // paths rouletted (constant survival before the thirtieth session: T = 0.0744 ± 0.0021).
  const double tau = 20.0;
  const Slab slab(tau);
  scene::Sun sun;
  sun.elevation_deg = 90.0;
  sun.intensity = 1.0;
  PathTracerSettings s = sunOnly(100000);
  s.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, 0.0};
  s.roulette_after_events = 128;
  s.sun_transmittance = SunTransmittance::Exact;  // low variance: no 0/1 ratio-tracking estimates
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), sun, s);
  const int n = 100000;
  PathTracerStats stats;
  auto flux = [&](double z, double sign, std::uint64_t stream0, double& se) {
    return diffuseFlux(pt, z, sign, n, stream0, se, &stats);
  };
  double seUp = 0.0, seDown = 0.0;
  // Measured beyond the zero-border ramps (β fades to 0 half a voxel, 250 m, outside the faces), so
  // that no medium lies beyond the measuring planes; in optical-depth coordinates the slab is
  // homogeneous and plane-parallel with τ = σ·1000 m all the same.
  const double reflected = flux(Slab::kBottom_m + Slab::kThickness_m + 251.0, -1.0, 1u << 22, seUp);
  const double transmitted = flux(Slab::kBottom_m - 251.0, 1.0, 1u << 23, seDown);
  const double tauStored = slab.sigma_per_m * Slab::kThickness_m;
  const double expectedT = 4.0 * (std::sqrt(3.0) / 4.0 * 2.90781) / (3.0 * (tauStored + 2.0 * 0.710446));
  std::printf("thick slab tau %.2f: T %.5f +- %.5f (van de Hulst %.5f), R %.4f +- %.4f, R + T %.4f, %llu rouletted\n",
              tauStored, transmitted, seDown, expectedT, reflected, seUp, reflected + transmitted,
              static_cast<unsigned long long>(stats.rouletted_paths));
  EXPECT_LT(seDown, 0.03 * expectedT);
  EXPECT_NEAR(transmitted, expectedT, 0.01 * expectedT + 4.0 * seDown);
  EXPECT_NEAR(reflected + transmitted, 1.0, 4.0 * std::hypot(seUp, seDown));
  EXPECT_EQ(stats.truncated_paths, 0u);
  EXPECT_GT(stats.rouletted_paths, 0u);
}

TEST(PathTracer, EarlyRouletteKeepsTheThickSlabsVarianceFinite) {
  // The same τ = 20 slab (transmitted paths take O(τ²) ≈ 400 collisions), its transmission with
  // Russian roulette from the 16th collision and from the 128th. The survival q_n = n/(n + 1) gives
  // a path that lives to its N-th collision the weight (N + 1)/D, so the variance of a transmitted
  // path grows like N/D: starting 8× earlier costs ≈ √8 in the standard error and halves the
  // collisions. With the constant survival q = 1 − 1/D used before (weight q^−K ≈ e^{K/D} after K
  // more collisions) a 400-collision path carried e^{24} at D = 16. Measured (D = 16 / 128, 40 000
  // paths): T 0.0756 ± 0.0067 / 0.0742 ± 0.0023, largest weight 51 / 6.9, 15.6 / 33.7 collisions
  // per path.
  const Slab slab(20.0);
  scene::Sun sun;
  sun.elevation_deg = 90.0;
  sun.intensity = 1.0;
  const double expectedT =
      4.0 * (std::sqrt(3.0) / 4.0 * 2.90781) / (3.0 * (slab.sigma_per_m * Slab::kThickness_m + 2.0 * 0.710446));
  double se[2] = {}, t[2] = {};
  PathTracerStats stats[2];
  const int depths[2] = {16, 128};
  for (int k = 0; k < 2; ++k) {
    PathTracerSettings s = sunOnly(100000);
    s.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, 0.0};
    s.roulette_after_events = depths[k];
    s.sun_transmittance = SunTransmittance::Exact;
    const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), sun, s);
    t[k] = diffuseFlux(pt, Slab::kBottom_m - 251.0, 1.0, 40000, 1u << 24, se[k], &stats[k]);
    std::printf("roulette from %d: T %.5f +- %.5f (van de Hulst %.5f), %llu rouletted, largest weight %.2f, "
                "%.1f collisions per path\n",
                depths[k], t[k], se[k], expectedT, static_cast<unsigned long long>(stats[k].rouletted_paths),
                stats[k].max_path_weight, double(stats[k].medium_collisions) / 40000.0);
    EXPECT_NEAR(t[k], expectedT, 0.01 * expectedT + 4.0 * se[k]) << "roulette from " << depths[k];
    EXPECT_EQ(stats[k].truncated_paths, 0u);
    EXPECT_GT(stats[k].rouletted_paths, 0u);
    // Linear growth: no weight beyond (N + 1)/D for the cap N (and far below it in practice).
    EXPECT_LE(stats[k].max_path_weight, (100000.0 + 1.0) / depths[k]);
  }
  EXPECT_LT(se[0], 4.0 * se[1]);
  EXPECT_LT(stats[0].max_path_weight, 200.0);
}

TEST(PathTracer, OpticallyThinSlabApproachesSingleScattering) {
  // Full multiple scattering of a thin slab (τ = 0.01) against the single-scattering closed form.
  // Higher orders add O(x) relative to L₁, x = τ(1/μ_s + 1/μ_v) (≈ 0.025 here): with a forward
  // peaked phase, light scattered once on the way in or out is mostly not lost but redirected
  // within a few degrees, i.e. L → L₁/(1 − x/2 + …) as g → 1. Measured (4e6 paths):
  // L/L₁ − 1 = 0.027 ± 0.008. Asserted: L₁ ≤ L ≤ (1 + 2x) L₁, each within 4 standard errors.
  const Slab slab(0.01);
  const SlabView view;
  PathTracerSettings s = sunOnly(100000);
  s.sun_transmittance = SunTransmittance::Exact;
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), view.sun, s);
  const PixelEstimate e = pt.estimateRay(view.origin, view.dir, 2000000, 3);
  const double exact = view.exact(slab, s.phase.water);
  const double x = 0.01 * (1.0 / view.sun.toSun().z + 1.0 / -view.dir.z);
  std::printf("thin slab: L/L1 - 1 = %.4f +- %.4f (x = %.4f)\n", e.rgb.x / exact - 1.0, e.standard_error.x / exact, x);
  EXPECT_LT(e.standard_error.x, 0.015 * exact);
  EXPECT_GE(e.rgb.x, exact - 4.0 * e.standard_error.x);
  EXPECT_LE(e.rgb.x, exact * (1.0 + 2.0 * x) + 4.0 * e.standard_error.x);
  EXPECT_EQ(e.stats.truncated_paths, 0u);
}

TEST(PathTracer, ErrorFallsAsInverseSquareRootOfSamples) {
  const Slab slab(0.5);
  const SlabView view;
  const PathTracer pt(slab.volumes, volume::frameOf(slab.volumes), view.sun, sunOnly(1));
  const double exact = view.exact(slab, pt.settings().phase.water);
  const int repeats = 32;
  std::vector<double> logN, logErr;
  for (int n : {64, 256, 1024, 4096, 16384}) {
    double sq = 0.0;
    for (int r = 0; r < repeats; ++r) {
      const double d =
          pt.estimateRay(view.origin, view.dir, n, 1000u * std::uint64_t(n) + std::uint64_t(r)).rgb.x - exact;
      sq += d * d;
    }
    logN.push_back(std::log(double(n)));
    logErr.push_back(0.5 * std::log(sq / repeats));
  }
  // Least-squares slope of log RMSE against log N.
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < logN.size(); ++i) mx += logN[i], my += logErr[i];
  mx /= double(logN.size());
  my /= double(logN.size());
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < logN.size(); ++i)
    sxy += (logN[i] - mx) * (logErr[i] - my), sxx += (logN[i] - mx) * (logN[i] - mx);
  const double slope = sxy / sxx;
  RecordProperty("slope", std::to_string(slope));
  EXPECT_NEAR(slope, -0.5, 0.15);
}

// A cloud of three overlapping Gaussian blobs, ice and water mixed, with peak optical depths ~5.
ExtinctionVolumes blobCloud() {
  ExtinctionVolumes v = emptyVolume(16, 16, 8, 500.0, 500.0, 2000.0);
  const glm::dvec3 c1(5.0, 6.0, 3.0), c2(10.0, 9.0, 4.0), c3(8.0, 4.0, 5.0);
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const glm::dvec3 p(i, j, k);
        auto blob = [&](const glm::dvec3& c, double r) { return std::exp(-glm::dot(p - c, p - c) / (r * r)); };
        v.water_per_m[v.index(i, j, k)] = float(2e-3 * (blob(c1, 2.5) + blob(c2, 2.0)));
        v.ice_per_m[v.index(i, j, k)] = float(1.5e-3 * blob(c3, 3.0));
      }
  v.updateMaxima();
  return v;
}

scene::Camera smallCamera(const volume::VolumeFrame& frame) {
  scene::Camera cam;
  const glm::dvec3 centre = 0.5 * (frame.min_m() + frame.max_m());
  cam.position_m = centre + glm::dvec3(-9000.0, -11000.0, 7000.0);
  cam.target_m = centre;
  cam.vertical_fov_deg = 40.0;
  cam.width = 16;
  cam.height = 16;
  return cam;
}

TEST(PathTracer, WhiteFurnace) {
  // Albedo 1, no sun, no ground, uniform sky L: the radiance along every ray is L, so the
  // cloud's part (RGB without background) must be alpha·L and with background exactly L.
  const ExtinctionVolumes v = blobCloud();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const scene::Camera cam = smallCamera(frame);
  PathTracerSettings s;
  s.sun_enabled = false;
  s.sky_radiance = {1.0, 0.5, 0.25};
  s.samples_per_pixel = 512;
  s.phase.ice = {physics::PhaseModel::CornetteShanks, 0.8};
  const PathTracedImage cloudOnly = PathTracer(v, frame, scene::Sun{}, s).render(cam);
  double sumRgb = 0.0, sumExpected = 0.0, var = 0.0, alphaMax = 0.0;
  for (int i = 0; i < cam.width * cam.height; ++i) {
    const double alpha = double(cloudOnly.rgba[4 * std::size_t(i) + 3]);
    alphaMax = std::max(alphaMax, alpha);
    for (int c = 0; c < 3; ++c) {
      sumRgb += double(cloudOnly.rgba[4 * std::size_t(i) + std::size_t(c)]) / s.sky_radiance[c];
      sumExpected += alpha;
      const double se = double(cloudOnly.standard_error[3 * std::size_t(i) + std::size_t(c)]) / s.sky_radiance[c];
      var += se * se;
    }
  }
  EXPECT_GT(alphaMax, 0.9);  // the scene has optically thick parts
  EXPECT_GT(sumExpected, 50.0);
  std::printf("white furnace: sum RGB/L / sum alpha = %.5f, z = %.2f\n", sumRgb / sumExpected,
              (sumRgb - sumExpected) / std::sqrt(var));
  EXPECT_NEAR(sumRgb, sumExpected, 4.0 * std::sqrt(var));
  EXPECT_NEAR(sumRgb / sumExpected, 1.0, 0.01);
  EXPECT_EQ(cloudOnly.stats.truncated_paths, 0u);
  // Multiple scattering happened: more than 2 collisions per path whose primary ray collides
  // (Σ alpha · spp of them in expectation).
  EXPECT_GT(double(cloudOnly.stats.medium_collisions), 2.0 * sumExpected / 3.0 * s.samples_per_pixel);

  s.include_background = true;
  const PathTracedImage full = PathTracer(v, frame, scene::Sun{}, s).render(cam);
  for (int i = 0; i < cam.width * cam.height; ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(double(full.rgba[4 * std::size_t(i) + std::size_t(c)]), s.sky_radiance[c], 1e-6) << "pixel " << i;
    }
  }

  // A white ground (albedo 1) under the same sky keeps the furnace: everything still sees L.
  s.ground_enabled = true;
  s.ground_albedo = glm::dvec3(1.0);
  s.samples_per_pixel = 32;
  const PathTracedImage grounded = PathTracer(v, frame, scene::Sun{}, s).render(cam);
  EXPECT_GT(grounded.stats.ground_hits, 0u);
  EXPECT_EQ(grounded.stats.truncated_paths, 0u);
  for (int i = 0; i < cam.width * cam.height; ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(double(grounded.rgba[4 * std::size_t(i) + std::size_t(c)]), s.sky_radiance[c], 1e-6) << "pixel " << i;
    }
  }
}

TEST(PathTracer, GroundOnlySceneMatchesClosedForm) {
  // Empty volume, Lambertian ground of albedo ρ under sun E at elevation e and sky L:
  // L_out = ρ (E sin e / π + L) for every pixel that sees the ground (with background on).
  const ExtinctionVolumes v = emptyVolume(8, 8, 4, 1000.0, 500.0, 1000.0);
  const volume::VolumeFrame frame = volume::frameOf(v);
  scene::Sun sun;
  sun.elevation_deg = 35.0;
  sun.intensity = 3.0;
  PathTracerSettings s;
  s.ground_enabled = true;
  s.ground_albedo = {0.3, 0.5, 0.7};
  s.sky_radiance = {0.2, 0.3, 0.4};
  s.include_background = true;
  s.samples_per_pixel = 4;
  const PathTracer pt(v, frame, sun, s);
  const PixelEstimate e = pt.estimateRay({4000.0, 4000.0, 5000.0}, glm::normalize(glm::dvec3(0.2, 0.1, -1.0)), 16, 0);
  for (int c = 0; c < 3; ++c) {
    const double expected =
        s.ground_albedo[c] * (sun.intensity * std::sin(35.0 * kPi / 180.0) / kPi + s.sky_radiance[c]);
    EXPECT_NEAR(e.rgb[c], expected, 1e-12);
  }
  EXPECT_EQ(e.alpha, 0.0);
  s.include_background = false;  // the ground is background: nothing left in RGB
  const PixelEstimate bg = PathTracer(v, frame, sun, s).estimateRay({4000.0, 4000.0, 5000.0}, {0.0, 0.0, -1.0}, 16, 0);
  EXPECT_EQ(bg.rgb, glm::dvec3(0.0));
}

TEST(PathTracer, DeterministicPerSeedAndThreadCount) {
  const ExtinctionVolumes v = blobCloud();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const scene::Camera cam = smallCamera(frame);
  scene::Sun sun;
  sun.elevation_deg = 30.0;
  PathTracerSettings s;
  s.samples_per_pixel = 8;
  s.sky_radiance = {0.1, 0.15, 0.3};
  s.ground_enabled = true;
  s.ground_albedo = {0.2, 0.2, 0.2};
  s.seed = 42;
  s.threads = 1;
  const PathTracedImage a = PathTracer(v, frame, sun, s).render(cam);
  s.threads = 2;
  const PathTracedImage b = PathTracer(v, frame, sun, s).render(cam);
  s.threads = 0;
  const PathTracedImage c = PathTracer(v, frame, sun, s).render(cam);
  s.seed = 43;
  const PathTracedImage d = PathTracer(v, frame, sun, s).render(cam);
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  EXPECT_EQ(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.rgba.data(), c.rgba.data(), a.rgba.size() * sizeof(float)), 0);
  EXPECT_NE(std::memcmp(a.rgba.data(), d.rgba.data(), a.rgba.size() * sizeof(float)), 0);
  // Alpha is exact, hence seed-independent and equal to renderAlpha; renderPixel reproduces
  // the image's pixel.
  const std::vector<float> alphaOnly = PathTracer(v, frame, sun, s).renderAlpha(cam);
  for (std::size_t i = 3; i < a.rgba.size(); i += 4) {
    EXPECT_EQ(a.rgba[i], d.rgba[i]);
    EXPECT_EQ(a.rgba[i], alphaOnly[i / 4]);
  }
  s.seed = 42;
  const PixelEstimate p = PathTracer(v, frame, sun, s).renderPixel(cam, 7, 9);
  EXPECT_EQ(float(p.rgb.y), a.pixel(7, 9).y);
  double lit = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4) lit += double(a.rgba[i]);
  EXPECT_GT(lit, 0.0);
}

}  // namespace
}  // namespace nph::reference
