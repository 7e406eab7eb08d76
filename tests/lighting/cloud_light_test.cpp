// The cloud-light functions of glsl/common/cloud_light.glsl (compiled as C++, lighting/cloud_light.h)
// and the column depths of volume/column_depth.h against closed forms (issue 12).
#include "lighting/cloud_light.h"

#include <array>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "volume/column_depth.h"
#include "volume/volume_frame.h"

namespace nph::lighting {
namespace {

TEST(CloudLight, PhaseIsADensityOverTheSphere) {
  // ∫ p dΩ = 2π ∫_{−1}^{1} p(μ) dμ = 1 for every g (Simpson, 20 000 intervals), and the isotropic
  // lobe is 1/(4π): the E·p convention of docs/rendering.md.
  for (double g : {0.0, 0.5, 0.75, 0.85, -0.3}) {
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double mu = -1.0 + 2.0 * i / n;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w * hgPhase(mu, g);
    }
    EXPECT_NEAR(2.0 * std::numbers::pi * sum * (2.0 / n) / 3.0, 1.0, 2e-3) << "g " << g;
  }
  EXPECT_NEAR(hgPhase(0.3, 0.0), 1.0 / (4.0 * std::numbers::pi), 1e-15);
  EXPECT_NEAR(mixedPhase(0.3, 0.25, 0.75, 0.85), 0.25 * hgPhase(0.3, 0.75) + 0.75 * hgPhase(0.3, 0.85), 1e-15);
}

TEST(CloudLight, DiffuseTransmittanceIsTheTwoStreamClosedForm) {
  EXPECT_EQ(diffuseTransmittance(0.0, 0.85), 1.0);
  EXPECT_NEAR(diffuseTransmittance(20.0, 0.85), 1.0 / (1.0 + 0.75 * 0.15 * 20.0), 1e-15);
  EXPECT_EQ(diffuseTransmittance(-1.0, 0.85), 1.0);  // negative depth clamps (never darker than clear)
  // Thick layers: ∝ 1/τ with the diffusion limit's slope 4/(3(1 − g)τ) (van de Hulst 1980).
  const double tau = 1e4, g = 0.85;
  EXPECT_NEAR(diffuseTransmittance(tau, g) * 0.75 * (1.0 - g) * tau, 1.0, 1e-3);
}

// The sky light inside a cloud (issue 12, twelfth session): the mean radiance I₀ of the conservative
// Eddington column lit by diffuse light from above and below. Uniform light all round gives the
// light itself at every depth (the white furnace: a non-absorbing medium cannot darken it); the
// former ½·(L_a·T_d(τ_up) + L_b·T_d(τ_down)) gave ½·(T_d + T_d)·L, 0.15·L deep in a τ = 100 deck.
TEST(CloudLight, SkyDiffuseKeepsTheWhiteFurnaceAndMatchesTheEddingtonColumn) {
  const glm::dvec3 L{0.3, 0.5, 0.9};
  for (double g : {0.0, 0.75, 0.85})
    for (double scale : {1.0, 0.226, 0.085})
      for (double tu : {0.0, 0.3, 5.0, 100.0})
        for (double td : {0.0, 2.0, 100.0}) {
          const glm::dvec3 s = skyDiffuse(tu, td, g, scale, L, L);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(s[c], L[c], 1e-12 * L[c]) << g << " " << scale << " " << tu << " " << td;
        }
  const glm::dvec3 a{1.0, 1.0, 1.0}, zero{0.0};
  // Clear air: the two hemispheres averaged, as before.
  EXPECT_NEAR(skyDiffuse(0.0, 0.0, 0.85, 1.0, a, zero).x, 0.5, 1e-15);
  // Black below: the cloud's base sends ½·L·T_d(τ*) (the former term there), its top
  // (⅔ + k·τ*)/(4/3 + k·τ*) → 1 for thick cloud (its reflectance), linear in between.
  const double g = 0.85, tau = 40.0, k = 1.0 - g;
  EXPECT_NEAR(skyDiffuse(tau, 0.0, g, 1.0, a, zero).x, 0.5 * diffuseTransmittance(tau, g), 1e-15);
  EXPECT_NEAR(skyDiffuse(0.0, tau, g, 1.0, a, zero).x, (2.0 / 3.0 + k * tau) / (4.0 / 3.0 + k * tau), 1e-15);
  EXPECT_NEAR(skyDiffuse(10.0, 30.0, g, 1.0, a, zero).x, (2.0 / 3.0 + k * 30.0) / (4.0 / 3.0 + k * tau), 1e-15);
  // Linear in the light (superposition of the two hemispheres).
  const glm::dvec3 b{0.2, 0.1, 0.05};
  const glm::dvec3 sum = skyDiffuse(7.0, 3.0, g, 0.5, a, zero) + skyDiffuse(7.0, 3.0, g, 0.5, zero, b);
  const glm::dvec3 both = skyDiffuse(7.0, 3.0, g, 0.5, a, b);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(both[c], sum[c], 1e-15);
  // The exaggeration's slower vertical diffusion: k = (1 − g)/scale.
  EXPECT_NEAR(skyDiffuse(0.0, 4.0, g, 0.5, a, zero).x, skyDiffuse(0.0, 8.0, g, 1.0, a, zero).x, 1e-15);
}

TEST(CloudLight, ClearSkyIsBlueOverheadFadesAtDuskAndScalesWithTheSun) {
  const glm::dvec3 noon = clearSkyRadiance(std::sin(60.0 * std::numbers::pi / 180.0));
  EXPECT_GT(noon.b, noon.g);
  EXPECT_GT(noon.g, noon.r);
  // Diffuse irradiance on the ground π·L against E: 0.05–0.2 of E at 60° (Bird & Hulstrom 1981).
  const double y = 0.2126 * noon.r + 0.7152 * noon.g + 0.0722 * noon.b;
  EXPECT_GT(std::numbers::pi * y, 0.05);
  EXPECT_LT(std::numbers::pi * y, 0.2);
  // Monotone in elevation above the horizon; 0 below civil twilight (−6°).
  double previous = -1.0;
  for (double deg = -10.0; deg <= 90.0; deg += 1.0) {
    const glm::dvec3 l = clearSkyRadiance(std::sin(deg * std::numbers::pi / 180.0));
    const double yl = l.r + l.g + l.b;
    EXPECT_GE(yl, previous - 1e-12) << deg << "°";
    EXPECT_TRUE(std::isfinite(yl));
    if (deg <= -7.0) {
      EXPECT_EQ(yl, 0.0) << deg << "°";
    }
    previous = yl;
  }
  // The Kasten–Young air mass: 1 at the zenith, ≈ 38 at the horizon.
  EXPECT_NEAR(airMass(1.0), 1.0, 1e-3);
  EXPECT_NEAR(airMass(0.0), 38.0, 0.2);
  // skyLightFor: above = clear sky × style × intensity; below = the ground's ρ/π of sun + sky.
  StyleSettings style;
  const SkyLight s = skyLightFor(style, 30.0, glm::dvec3(1.0), 2.0);
  const glm::dvec3 sky = 2.0 * clearSkyRadiance(0.5);
  EXPECT_NEAR(s.above.g, sky.g, 1e-12);
  EXPECT_NEAR(s.below.g, style.ground_albedo / std::numbers::pi * (2.0 * 0.5 + std::numbers::pi * sky.g), 1e-12);
  style.sky_below = true;
  EXPECT_EQ(skyLightFor(style, 30.0, glm::dvec3(1.0), 2.0).below, skyLightFor(style, 30.0, glm::dvec3(1.0), 2.0).above);
}

// The two-stream term's moments at optical depth τ_a of a slab τ_a + τ_b, per unit irradiance:
// I₀ (μ_out = 0) and I₁ from S(μ_out = ±1) = I₀ ± g·I₁, at true scale (beam and diffusion scale
// 1). S is clamped at 0 (where the Eddington truncation would make it negative: looking against a
// strong net flux with g > ⅔), so I₁ is read from the side that is not clamped.
struct Moments {
  double i0, i1;
};
Moments twoStreamMoments(double tau_a, double tau_b, double mu0, double g) {
  const double i0 = twoStreamDiffuse(tau_a, tau_b, mu0, 1.0, 1.0, 0.0, g);
  const double up = twoStreamDiffuse(tau_a, tau_b, mu0, 1.0, 1.0, 1.0, g);
  const double down = twoStreamDiffuse(tau_a, tau_b, mu0, 1.0, 1.0, -1.0, g);
  return {i0, up > 0.0 ? (up - i0) / g : (i0 - down) / g};
}

TEST(CloudLight, TwoStreamSlabReflectsJosephWiscombeWeinmanAndConservesEnergy) {
  // Reflectance F↑(0)/(μ₀E) of the diffuse field at the top, F↑ = π(I₀ + ⅔I₁) (Eddington), against
  // the conservative δ-Eddington closed form of Joseph, Wiscombe & Weinman 1976:
  // R = [(1 − g')τ' + (⅔ − μ₀)(1 − e^{−τ'/μ₀})] / (4/3 + (1 − g')τ'), τ' = (1 − g²)τ, g' = g/(1 + g).
  const double pi = std::numbers::pi;
  for (double g : {0.05, 0.5, 0.85}) {
    for (double mu0 : {1.0, 0.6, 0.2}) {
      for (double tau : {0.5, 5.0, 20.0, 100.0}) {
        const Moments top = twoStreamMoments(0.0, tau, mu0, g);
        const double r = pi * (top.i0 + 2.0 / 3.0 * top.i1) / mu0;
        const double ts = (1.0 - g * g) * tau, k = 1.0 - g / (1.0 + g);
        const double expected = (k * ts + (2.0 / 3.0 - mu0) * (1.0 - std::exp(-ts / mu0))) / (4.0 / 3.0 + k * ts);
        EXPECT_NEAR(r, expected, 1e-12) << "g " << g << " mu0 " << mu0 << " tau " << tau;
        // No diffuse light enters at the bottom, and the net flux (diffuse up (4π/3)·I₁ minus the
        // direct beam μ₀e^{−τ'/μ₀} down) is the same at every depth: −μ₀·(1 − R), nothing absorbed.
        const Moments bottom = twoStreamMoments(tau, 0.0, mu0, g);
        EXPECT_NEAR(bottom.i0 + 2.0 / 3.0 * bottom.i1, 0.0, 1e-12);
        for (double f : {0.0, 0.3, 0.7, 1.0}) {
          const Moments m = twoStreamMoments(f * tau, (1.0 - f) * tau, mu0, g);
          const double net = 4.0 * pi / 3.0 * m.i1 - mu0 * std::exp(-(1.0 - g * g) * f * tau / mu0);
          EXPECT_NEAR(net, -mu0 * (1.0 - r), 1e-9) << "g " << g << " mu0 " << mu0 << " tau " << tau << " at " << f;
        }
      }
    }
  }
  // The thick conservative slab of van de Hulst 1980 (vol. 2 ch. 14; tests/reference's path-tracer
  // check): isotropic scattering (g → 0), sun at the zenith, τ = 20: T = 4K(1)/(3(τ + 2q₀)) =
  // 0.07837. The Eddington slab's T = 1 − R is within 0.5 % of it (measured −0.33 %).
  const Moments top = twoStreamMoments(0.0, 20.0, 1.0, 1e-9);
  const double transmittance = 1.0 - pi * (top.i0 + 2.0 / 3.0 * top.i1);
  EXPECT_NEAR(transmittance, 0.07837, 0.005 * 0.07837);
  // A thin layer scatters little: R → τ'(…) → 0, and the term is never negative or NaN.
  EXPECT_NEAR(twoStreamDiffuse(0.0, 0.0, 0.7, 1.0, 1.0, 1.0, 0.85), 0.0, 1e-15);
  EXPECT_EQ(twoStreamDiffuse(3.0, 4.0, 0.0, 1.0, 1.0, 1.0, 0.85), 0.0);  // the sun has set
  EXPECT_TRUE(std::isfinite(twoStreamDiffuse(1e4, 1e4, 1e-4, 50.0, 0.01, -1.0, 0.99)));
}

// twoStreamColumn (the thirteenth session's candidates, docs/accuracy.md): with K = 1 and b = ⅔ it
// is twoStreamDiffuse; for any resistance k, drift constant K and Marshak constant b its moments
// solve the column's equations — dI₁/dτ' = −¾F·e^{−τ'/μ₀}, dI₀/dτ' = k·I₁ + ¾F(K − k)μ₀·e^{−τ'/μ₀}
// (central differences), I₀ ∓ b·I₁ = 0 at the top and the bottom — and conserve energy: the net
// flux (4π/3)·I₁ − B·μ₀·e^{−τ'/μ₀} (B the beam scale) is the same at every depth.
TEST(CloudLight, TwoStreamColumnSolvesItsEquationsForAnyConstants) {
  const double pi = std::numbers::pi;
  for (double tau : {0.5, 5.0, 40.0})
    for (double mu0 : {0.9, 0.3, 0.05}) {
      const glm::dvec3 sf = twoStreamSunFrame(0.5, 8.0);
      for (double muOut : {0.0, 0.8, -0.6})
        EXPECT_NEAR(
            twoStreamColumn(0.3 * tau, 0.7 * tau, mu0, sf.y, (1.0 - 0.85 / 1.85) / sf.z, 1.0, 2.0 / 3.0, muOut, 0.85),
            twoStreamDiffuse(0.3 * tau, 0.7 * tau, mu0, sf.y, sf.z, muOut, 0.85), 1e-12);
    }
  const double g = 0.75, f = g * g, beamScale = 2.5;
  struct Constants {
    double k, K, b;
  };
  for (const Constants c : {Constants{0.57, 1.0, 2.0 / 3.0}, Constants{6.7, 11.7, 2.0 / 3.0}, Constants{6.7, 1.0, 3.0},
                            Constants{0.3, 4.0, 1.5}})
    for (double tau : {0.5, 5.0, 40.0})
      for (double mu0 : {0.9, 0.3, 0.05}) {
        // Moments at the δ-scaled depth t of the slab τ.
        auto moments = [&](double t) {
          const double ta = t / (1.0 - f);
          return twoStreamColumnMoments(ta, tau - ta, mu0, beamScale, c.k, c.K, c.b, g);
        };
        const double tt = (1.0 - f) * tau, F = beamScale / pi, scale = F * mu0;
        const glm::dvec2 top = moments(0.0), bottom = moments(tt);
        EXPECT_NEAR(top.x - c.b * top.y, 0.0, 1e-9 * scale) << tau << " " << mu0;
        EXPECT_NEAR(bottom.x + c.b * bottom.y, 0.0, 1e-9 * scale) << tau << " " << mu0;
        const double net0 = 4.0 * pi / 3.0 * top.y - beamScale * mu0;
        for (double frac : {0.1, 0.5, 0.9}) {
          const double t = frac * tt, h = 1e-5 * std::max(tt, 1.0);
          const glm::dvec2 m = moments(t), lo = moments(t - h), hi = moments(t + h);
          const double beam = std::exp(-t / mu0);
          EXPECT_NEAR(4.0 * pi / 3.0 * m.y - beamScale * mu0 * beam, net0, 1e-9) << tau << " " << mu0;
          EXPECT_NEAR((hi.y - lo.y) / (2.0 * h), -0.75 * F * beam, 1e-5 * (1.0 + F)) << tau << " " << mu0;
          EXPECT_NEAR((hi.x - lo.x) / (2.0 * h), c.k * m.y + 0.75 * F * (c.K - c.k) * mu0 * beam,
                      1e-5 * (1.0 + F * c.K))
              << tau << " " << mu0 << " k " << c.k << " K " << c.K;
        }
      }
}

// forwardLobe (the thirteenth session): its premise, HG(g₁) ⊗ HG(g₂) = HG(g₁g₂) — light scattered
// by one lobe about the sun and then by another towards the eye — checked by quadrature over the
// sphere; and it only reshapes: ∫ forwardLobe dΩ = 0 (both lobes normalised), for the cone's light
// (sunlight above the direct beam) and the first diffuse order alike; 0 when the sun has set.
TEST(CloudLight, ForwardLobeConvolvesTheLobesAndAddsNoEnergy) {
  const double pi = std::numbers::pi;
  const int n = 400;  // midpoint rule in cos θ and φ
  for (double g1 : {0.3, 0.75, 0.85})
    for (double g2 : {0.43, 0.75})
      for (double psiDeg : {0.0, 35.0, 120.0}) {
        const double psi = psiDeg * pi / 180.0;
        // Both lobes on the grid's equator, where the midpoint rule in cos θ is finest in angle.
        const glm::dvec3 sun(1.0, 0.0, 0.0), eye(std::cos(psi), std::sin(psi), 0.0);
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < 2 * n; ++j) {
            const double c = -1.0 + (i + 0.5) * 2.0 / n, phi = (j + 0.5) * pi / n, sn = std::sqrt(1.0 - c * c);
            const glm::dvec3 w(sn * std::cos(phi), sn * std::sin(phi), c);
            sum += hgPhase(glm::dot(w, sun), g1) * hgPhase(glm::dot(w, eye), g2) * (2.0 / n) * (pi / n);
          }
        EXPECT_NEAR(sum, hgPhase(std::cos(psi), g1 * g2), 2e-3 * hgPhase(std::cos(psi), g1 * g2))
            << g1 << " " << g2 << " " << psiDeg;
      }
  for (double g : {0.75, 0.85})
    for (double tauAbove : {0.0, 0.05, 1.0, 30.0})
      for (double sunlight : {0.0, 0.3, 1.0}) {
        double integral = 0.0;
        const int m = 200000;
        for (int i = 0; i < m; ++i) {
          const double c = -1.0 + (i + 0.5) * 2.0 / m;
          integral += 2.0 * pi * forwardLobe(sunlight, c, g, tauAbove, 0.2) * 2.0 / m;
        }
        EXPECT_NEAR(integral, 0.0, 1e-6) << g << " " << tauAbove << " " << sunlight;
      }
  EXPECT_EQ(forwardLobe(0.5, 0.8, 0.85, 1.0, 0.0), 0.0);
  // At a 35° forward angle the cone's light is seen brighter than by p(ψ; g) alone (the cirrus).
  EXPECT_GT(forwardLobe(0.8, std::cos(35.0 * pi / 180.0), 0.75, 0.1, 0.05), 0.0);
}

TEST(CloudLight, TwoStreamSunFrameKeepsTheSlantedOpticalDepthOfTheExaggeratedWorld) {
  // At true scale the frame is (μ_w, 1, 1).
  const glm::dvec3 one = twoStreamSunFrame(0.6, 1.0);
  EXPECT_NEAR(one.x, 0.6, 1e-12);
  EXPECT_NEAR(one.y, 1.0, 1e-12);
  EXPECT_NEAR(one.z, 1.0, 1e-12);
  ExtinctionVolumes v = ExtinctionVolumes::zeros(2, 2, 2, 1000.0, 100.0, 0.0);
  for (double e : {2.0, 4.0, 8.0}) {
    const volume::VolumeFrame f = volume::frameOf(v, e);
    for (double elevationDeg : {5.0, 30.0, 70.0}) {
      const double h = elevationDeg * std::numbers::pi / 180.0;
      const glm::dvec3 d(std::cos(h), 0.0, std::sin(h));
      const glm::dvec3 frame = twoStreamSunFrame(d.z, e);
      // A world layer of height H: the beam's optical depth over its vertical one is 1/μ₀
      // (VolumeFrame::opticalDepthScale, the integrators' rule).
      const double slant = f.opticalDepthScale(d) / d.z, vertical = f.opticalDepthScale({0.0, 0.0, 1.0});
      EXPECT_NEAR(frame.x, vertical / slant, 1e-12) << e << " " << elevationDeg;
      EXPECT_NEAR(frame.y * frame.x, d.z, 1e-12);  // the horizontal flux E·μ_w is kept
    }
    // The diffusion scale 3⟨(d_z/(e·f(d)))²⟩ over the sphere of world directions (midpoint rule).
    const int n = 200000;
    double mean = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = (i + 0.5) / n;
      mean += 3.0 * mu * mu / (e * e * (1.0 - mu * mu) + mu * mu) / n;
    }
    EXPECT_NEAR(twoStreamSunFrame(0.5, e).z, mean, 1e-6) << e;
  }
}

TEST(ColumnDepth, SumsTheColumnAboveAndBelowAtTheDataScale) {
  // One column of 4 layers, dz = 100 m, β = 1e-3, 2e-3, 0, 4e-3 /m (bottom to top).
  ExtinctionVolumes v = ExtinctionVolumes::zeros(1, 1, 4, 1000.0, 100.0, 0.0);
  v.water_per_m = {1e-3f, 2e-3f, 0.0f, 4e-3f};
  const ColumnDepths d = columnDepths(v);
  EXPECT_NEAR(d.up[0], 0.05 + 0.2 + 0.0 + 0.4, 1e-3);  // half precision (the GPU texture)
  EXPECT_NEAR(d.up[3], 0.2, 1e-3);
  EXPECT_NEAR(d.down[0], 0.05, 1e-3);
  EXPECT_NEAR(d.down[3], 0.1 + 0.2 + 0.2, 1e-3);
  // Height exaggeration changes world heights, not the depths (the data's optical depth).
  const volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  const glm::dvec3 centre1 = frame.worldFromGrid(glm::dvec3(0.5, 0.5, 1.5));
  EXPECT_NEAR(columnDepthAt(d, frame, centre1).x, 0.1 + 0.4, 1e-3);
  // Halfway between layer centres 1 and 2: the mean; above the top: clamped to the top centre.
  const glm::dvec3 between = frame.worldFromGrid(glm::dvec3(0.5, 0.5, 2.0));
  EXPECT_NEAR(columnDepthAt(d, frame, between).x, 0.5 * (0.5 + 0.4), 1e-3);
  EXPECT_NEAR(columnDepthAt(d, frame, frame.worldFromGrid(glm::dvec3(0.5, 0.5, 9.0))).x, 0.2, 1e-3);
}

TEST(ColumnDepth, CubicDepthsAreTheBSplineOfTheVoxelDepthsClampedToTheEdge) {
  // The column's up depths (0.65, 0.5, 0.4, 0.2 bottom to top, as above) read by the cubic
  // B-spline (volume/reconstruction.h): at a voxel centre the weights are 1/6, 2/3, 1/6 of the
  // layers below, at and above; past the grid the edge voxel repeats (GL_CLAMP_TO_EDGE). A
  // horizontal neighbour column of twice the extinction enters with the same weights across.
  ExtinctionVolumes v = ExtinctionVolumes::zeros(2, 1, 4, 1000.0, 100.0, 0.0);
  for (int k = 0; k < 4; ++k) {
    const float b = std::array{1e-3f, 2e-3f, 0.0f, 4e-3f}[std::size_t(k)];
    v.water_per_m[v.index(0, 0, k)] = b;
    v.water_per_m[v.index(1, 0, k)] = 2.0f * b;
  }
  const ColumnDepths d = columnDepths(v, volume::Reconstruction::Cubic);
  const volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  const double up0[4] = {0.65, 0.5, 0.4, 0.2};
  // Column x = 0 at the centre of layer 1: x-weights 1/6 (clamped: itself) + 2/3 + 1/6 (column 1).
  const double ownAt1 = (up0[0] + 4.0 * up0[1] + up0[2]) / 6.0;
  EXPECT_NEAR(columnDepthAt(d, frame, frame.worldFromGrid(glm::dvec3(0.5, 0.5, 1.5))).x,
              (5.0 / 6.0) * ownAt1 + (1.0 / 6.0) * 2.0 * ownAt1, 2e-3);
  // The top centre: the layer above is the edge (0.2 again).
  const double ownAt3 = (up0[2] + 4.0 * up0[3] + up0[3]) / 6.0;
  EXPECT_NEAR(columnDepthAt(d, frame, frame.worldFromGrid(glm::dvec3(0.5, 0.5, 3.5))).x, (7.0 / 6.0) * ownAt3, 2e-3);
  // Trilinear depths of the same volume still interpolate the voxels.
  const ColumnDepths tri = columnDepths(v);
  EXPECT_NEAR(columnDepthAt(tri, frame, frame.worldFromGrid(glm::dvec3(0.5, 0.5, 1.5))).x, 0.5, 1e-3);
}

TEST(VolumeFrame, OpticalDepthScaleKeepsTheDataDepthAlongEveryDirection) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(2, 2, 2, 1000.0, 100.0, 0.0);
  const volume::VolumeFrame f = volume::frameOf(v, 8.0);
  EXPECT_NEAR(f.opticalDepthScale({0.0, 0.0, 1.0}), 1.0 / 8.0, 1e-15);
  EXPECT_NEAR(f.opticalDepthScale({1.0, 0.0, 0.0}), 1.0, 1e-15);
  // A slanted world path between two grid points has the length of the unexaggerated path.
  const glm::dvec3 a = f.worldFromGrid({0.2, 0.3, 0.1}), b = f.worldFromGrid({1.7, 1.1, 1.9});
  const double world = glm::length(b - a);
  const glm::dvec3 realDelta = (b - a) * glm::dvec3(1.0, 1.0, 1.0 / 8.0);
  EXPECT_NEAR(world * f.opticalDepthScale(b - a), glm::length(realDelta), 1e-9);
}

}  // namespace
}  // namespace nph::lighting
