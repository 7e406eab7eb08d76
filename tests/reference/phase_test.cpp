// Phase functions and cumulative phase (src/physics/phase.h): normalisation, CP end points and
// monotonicity, HG closed form against quadrature, CS table against its analytic antiderivative,
// sampling against the density.
#include "physics/phase.h"

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace nph::physics {
namespace {

constexpr double kPi = std::numbers::pi;

// ∫_{4π} p dΩ = 2π ∫_{-1}^{1} p(μ) dμ by composite Simpson in θ (dμ = sin θ dθ) — independent of
// the library's Gauss–Legendre quadrature. 2e5 panels resolve the g = 0.95 forward peak.
double sphereIntegral(const PhaseFunction& p) {
  const int n = 200000;
  const double h = kPi / n;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = i * h;
    const double f = p.eval(std::cos(t)) * std::sin(t);
    s += (i == 0 || i == n) ? f : (i % 2 ? 4.0 * f : 2.0 * f);
  }
  return 2.0 * kPi * s * h / 3.0;
}

// Analytic CP of Cornette–Shanks (for the test only; the library tabulates numerically).
// With u = a − bμ, a = 1 + g², b = 2g: ∫ (1 + μ²) u^{-3/2} dμ = −(1/b) F(u),
// F(u) = −2u^{-1/2} + (−2a² u^{-1/2} − 4a u^{1/2} + (2/3) u^{3/2}) / b².
long double csCumulativeExact(long double theta, long double g) {
  const long double a = 1 + g * g, b = 2 * g;
  const long double k = 3 * (1 - g * g) / (2 * (2 + g * g));
  auto F = [&](long double u) {
    return -2 / std::sqrt(u) +
           (-2 * a * a / std::sqrt(u) - 4 * a * std::sqrt(u) + 2.0L / 3.0L * u * std::sqrt(u)) / (b * b);
  };
  const long double uc = a - b * std::cos(theta), u1 = (1 - g) * (1 - g);
  return 0.5L * k * (F(uc) - F(u1)) / b;
}

class PhaseParam : public ::testing::TestWithParam<PhaseFunction> {};

TEST_P(PhaseParam, NormalisedOverTheSphere) { EXPECT_NEAR(sphereIntegral(GetParam()), 1.0, 1e-6); }

TEST_P(PhaseParam, CumulativeEndPointsAndMonotone) {
  const CumulativePhaseTable cp(GetParam());
  EXPECT_LT(cp.maxInterpolationError(), 1e-7);
  EXPECT_EQ(cp(0.0), 0.0);
  EXPECT_NEAR(cp(kPi), 1.0, 1e-9);
  EXPECT_NEAR(cumulativePhase(GetParam(), kPi), 1.0, 1e-9);
  EXPECT_NEAR(cumulativePhase(GetParam(), 0.0), 0.0, 1e-15);
  double prev = 0.0;
  for (int i = 1; i <= 20000; ++i) {
    const double v = cp(kPi * i / 20000.0);
    ASSERT_GE(v, prev - 1e-12) << "theta index " << i;
    prev = v;
  }
}

TEST_P(PhaseParam, TableAgreesWithExactCumulative) {
  const PhaseFunction p = GetParam();
  const CumulativePhaseTable cp(p);
  double worst = 0.0;
  for (int i = 0; i <= 7919; ++i) {  // a prime count so the points fall between the nodes
    const double t = kPi * i / 7919.0;
    const double exact = p.model == PhaseModel::HenyeyGreenstein ? henyeyGreensteinCumulative(t, p.g)
                                                                 : double(csCumulativeExact(t, p.g));
    worst = std::max(worst, std::abs(cp(t) - exact));
  }
  EXPECT_LT(worst, 1e-6);
}

TEST_P(PhaseParam, SamplingMatchesTheDensity) {
  // Histogram of sampled μ in 20 bins against the exact bin probabilities (CP differences).
  const PhaseFunction p = GetParam();
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto next = [&] { return uni(rng); };
  const int n = 400000, bins = 20;
  std::vector<int> count(bins, 0);
  for (int i = 0; i < n; ++i) {
    const double mu = p.sampleCos(next);
    ++count[std::min(bins - 1, int((mu + 1.0) * 0.5 * bins))];
  }
  for (int b = 0; b < bins; ++b) {
    const double mu0 = -1.0 + 2.0 * b / bins, mu1 = mu0 + 2.0 / bins;
    const double prob = cumulativePhase(p, std::acos(mu0)) - cumulativePhase(p, std::acos(mu1));
    const double sigma = std::sqrt(n * prob * (1 - prob)) + 1.0;
    EXPECT_NEAR(count[b], n * prob, 5.0 * sigma) << "bin " << b;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, PhaseParam,
                         ::testing::Values(PhaseFunction{PhaseModel::HenyeyGreenstein, 0.0},
                                           PhaseFunction{PhaseModel::HenyeyGreenstein, 0.85},
                                           PhaseFunction{PhaseModel::HenyeyGreenstein, 0.75},
                                           PhaseFunction{PhaseModel::HenyeyGreenstein, -0.4},
                                           PhaseFunction{PhaseModel::HenyeyGreenstein, 0.95},
                                           PhaseFunction{PhaseModel::CornetteShanks, 0.9},
                                           PhaseFunction{PhaseModel::CornetteShanks, 0.5},
                                           PhaseFunction{PhaseModel::CornetteShanks, 0.95}),
                         [](const ::testing::TestParamInfo<PhaseFunction>& param_info) {
                           std::string name = param_info.param.model == PhaseModel::HenyeyGreenstein ? "HG_g" : "CS_g";
                           const int milli = int(std::lround(param_info.param.g * 1000.0));
                           return name + (milli < 0 ? "minus" : "") + std::to_string(std::abs(milli));
                         });

TEST(Phase, HenyeyGreensteinClosedFormAgainstQuadrature) {
  for (double g : {-0.5, 0.0, 1e-9, 0.3, 0.85, 0.99}) {
    for (double t : {1e-4, 0.01, 0.1, 0.5, 1.0, 2.0, 3.0, kPi}) {
      // Simpson over [0, t] of 2π p sin.
      const int n = 20000;
      const double h = t / n;
      double s = 0.0;
      for (int i = 0; i <= n; ++i) {
        const double f = henyeyGreenstein(std::cos(i * h), g) * std::sin(i * h);
        s += (i == 0 || i == n) ? f : (i % 2 ? 4.0 * f : 2.0 * f);
      }
      EXPECT_NEAR(henyeyGreensteinCumulative(t, g), 2.0 * kPi * s * h / 3.0, 1e-8) << "g " << g << " theta " << t;
    }
  }
}

TEST(Phase, KnownValues) {
  EXPECT_NEAR(henyeyGreenstein(0.3, 0.0), 1.0 / (4.0 * kPi), 1e-15);
  EXPECT_NEAR(cornetteShanks(0.5, 0.0), 3.0 / (16.0 * kPi) * 1.25, 1e-15);  // Rayleigh
  EXPECT_NEAR(henyeyGreensteinCumulative(kPi / 2, 0.0), 0.5, 1e-15);
  // CS mean cosine (Cornette & Shanks 1992 eq. 9) by quadrature.
  const double g = 0.9;
  const int n = 200000;
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mu = -1.0 + (i + 0.5) * 2.0 / n;
    s += cornetteShanks(mu, g) * mu;
  }
  EXPECT_NEAR(2.0 * kPi * s * 2.0 / n, 3.0 * g * (4.0 + g * g) / (5.0 * (2.0 + g * g)), 1e-5);
}

TEST(Phase, MixFollowsNesEq512) {
  const PhaseMix mix;  // defaults: ice HG 0.75, water HG 0.85
  EXPECT_EQ(mix.ice.g, kIceEyeAsymmetry);
  EXPECT_EQ(mix.water.g, kWaterEyeAsymmetry);
  const double c = 0.2;
  EXPECT_NEAR(mix.eval(c, 1.0, 3.0), 0.25 * mix.ice.eval(c) + 0.75 * mix.water.eval(c), 1e-15);
  EXPECT_NEAR(mix.eval(c, 2e-3, 0.0), mix.ice.eval(c), 1e-15);
  EXPECT_NEAR(mix.eval(c, 0.0, 2e-3), mix.water.eval(c), 1e-15);
  EXPECT_TRUE(std::isfinite(mix.eval(c, 0.0, 0.0)));
}

TEST(Phase, RejectsInvalidAsymmetry) {
  EXPECT_ANY_THROW(CumulativePhaseTable(PhaseFunction{PhaseModel::CornetteShanks, 1.0}));
  EXPECT_ANY_THROW(cumulativePhase(PhaseFunction{PhaseModel::HenyeyGreenstein, -1.5}, 0.3));
}

}  // namespace
}  // namespace nph::physics
