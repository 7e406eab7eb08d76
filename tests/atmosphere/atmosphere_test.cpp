// The atmosphere model on the CPU (atmosphere/atmosphere.h): normalisation, closed forms of a
// homogeneous test atmosphere, and the colour ordering of a clear sky (issue 14 "Done means").
#include "atmosphere/atmosphere.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "homogeneous_atmosphere.h"

namespace nph::atmosphere {
namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 viewDir(double elevation_deg, double azimuth_deg) {
  const double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

// ∫ p dΩ = 1 for both phase functions (midpoint rule in cos θ, 20 000 bands).
TEST(AtmosphereModel, PhaseFunctionsIntegrateToOne) {
  const int n = 20000;
  double rayleigh = 0.0, mie = 0.0;
  for (int i = 0; i < n; ++i) {
    const double c = -1.0 + (i + 0.5) * 2.0 / n;
    rayleigh += rayleighPhase(c) * 2.0 * kPi * 2.0 / n;
    mie += miePhase(c, 0.8) * 2.0 * kPi * 2.0 / n;
  }
  EXPECT_NEAR(rayleigh, 1.0, 1e-8);
  EXPECT_NEAR(mie, 1.0, 1e-4);  // the forward peak is steep; 1e-4 is the quadrature's error
}

// A homogeneous layer: the transmittance to the top is e^{−σ_t·L} with L the chord to the top
// sphere, to the quadrature's rounding.
TEST(AtmosphereModel, HomogeneousTransmittanceIsBeerLambert) {
  const Parameters p = test::homogeneousAtmosphere();
  const glm::dvec3 sigma = mediumAt(p, 0.0).extinction_per_m;
  for (double mu : {1.0, 0.5, 0.1, 0.0, -0.05}) {
    const double r = p.bottom_radius_m + 1000.0;
    const glm::dvec3 t = transmittanceToTop(p, r, mu, 16);
    const double length = distanceToTop(p, r, mu);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c], std::exp(-sigma[c] * length), 1e-12) << "mu " << mu;
  }
}

// Aerial perspective of the homogeneous test atmosphere, single scattering, plane-parallel, a
// horizontal segment (constant altitude, so T_sun is the same everywhere along it):
// T = e^{−σ_t d}, L_in = σ_s/σ_t · T_sun · p(θ) · (1 − e^{−σ_t d}).
TEST(AtmosphereModel, HomogeneousAerialPerspectiveHasTheClosedForm) {
  const Parameters p = test::homogeneousAtmosphere();
  const Quadrature q;
  const glm::dvec3 to_sun = viewDir(30.0, 40.0);
  const glm::dvec3 dir = viewDir(0.0, 0.0);
  const glm::dvec3 origin = observerAt(p, 2000.0);
  for (double d : {1000.0, 10000.0, 40000.0}) {
    const Segment s = integrateSegment(p, origin, dir, d, to_sun, q, /*plane_parallel=*/true);
    const test::ClosedForm cf = test::homogeneousClosedForm(p, 2000.0, to_sun, dir, d);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.transmittance[c], cf.transmittance[c], 1e-12) << "d " << d;
      EXPECT_NEAR(s.inscattered[c], cf.inscattered[c], 1e-9 * cf.inscattered[c] + 1e-15) << "d " << d;
    }
  }
}

// Clear sky at noon (sun 70° high): the zenith is bluer than the horizon (B/R larger), the
// horizon being whitened by the long path (Rayleigh's blue scattered out, Mie added).
TEST(AtmosphereModel, NoonZenithIsBluerThanTheHorizon) {
  const Parameters p = Parameters::earth();
  const Quadrature q;
  const glm::dvec3 x = observerAt(p, 200.0), to_sun = viewDir(70.0, 0.0);
  const glm::dvec3 zenith = skyRadiance(p, x, viewDir(90.0, 0.0), to_sun, q);
  const glm::dvec3 horizon = skyRadiance(p, x, viewDir(2.0, 90.0), to_sun, q);
  EXPECT_GT(zenith.b / zenith.r, horizon.b / horizon.r);
  EXPECT_GT(zenith.b, zenith.r);  // and blue at all
}

// Sunset (sun 1° high): the horizon towards the sun is redder (R/B larger) than the zenith.
TEST(AtmosphereModel, SunsetHorizonTowardsTheSunIsRedderThanTheZenith) {
  const Parameters p = Parameters::earth();
  const Quadrature q;
  const glm::dvec3 x = observerAt(p, 200.0), to_sun = viewDir(1.0, 0.0);
  const glm::dvec3 zenith = skyRadiance(p, x, viewDir(90.0, 0.0), to_sun, q);
  const glm::dvec3 horizon = skyRadiance(p, x, viewDir(3.0, 10.0), to_sun, q);
  EXPECT_GT(horizon.r / horizon.b, zenith.r / zenith.b);
  EXPECT_GT(horizon.r, horizon.b);  // and red at all
}

// The sky irradiance of a horizontal surface falls with the sun and stays positive in twilight.
TEST(AtmosphereModel, SkyIrradianceFallsWithTheSun) {
  const Parameters p = Parameters::earth();
  Quadrature q;
  q.view_steps = 32;  // a coarse quadrature: the ordering, not the value, is tested here
  q.ms_directions_mu = q.ms_directions_phi = 6;
  q.ms_steps = 16;
  q.irradiance_mu = q.irradiance_phi = 4;
  const glm::dvec3 noon = skyIrradiance(p, 0.0, 60.0 * kPi / 180.0, q);
  const glm::dvec3 low = skyIrradiance(p, 0.0, 5.0 * kPi / 180.0, q);
  const glm::dvec3 twilight = skyIrradiance(p, 0.0, -4.0 * kPi / 180.0, q);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(noon[c], low[c]);
    EXPECT_GT(low[c], twilight[c]);
    EXPECT_GT(twilight[c], 0.0);
  }
  // A clear noon sky gives the ground roughly 10–20 % of the sun's irradiance, bluish.
  EXPECT_GT(noon.b, noon.r);
  EXPECT_GT(noon.g, 0.03);
  EXPECT_LT(noon.g, 0.3);
}

}  // namespace
}  // namespace nph::atmosphere
