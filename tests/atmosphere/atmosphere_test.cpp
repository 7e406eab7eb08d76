// The atmosphere model on the CPU (atmosphere/atmosphere.h): normalisation, closed forms of a
// homogeneous test atmosphere, and the colour ordering of a clear sky (issue 14 "Done means").
#include "atmosphere/atmosphere.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// The flat view's point carried onto the planet (the clouds' aerial perspective): the chord from
// the eye ends at the point's altitude, at the ground angle D/R in the flat ray's azimuth; close by
// it is the flat ray itself; a point beyond the horizon is reached through the ground.
TEST(AtmosphereModel, FlatPointOnTheRoundPlanetKeepsItsAltitudeAndGroundDistance) {
  const Parameters p = Parameters::earth();
  const double R = p.bottom_radius_m, eye = 6000.0;
  for (double d : {1000.0, 100000.0, 300000.0, 2000000.0}) {
    for (double h : {0.0, 2000.0, 12000.0, 150000.0}) {
      const glm::dvec3 v(d * std::cos(0.4), d * std::sin(0.4), h - eye);
      const RoundChord c = flatPointOnRoundPlanet(p, eye, glm::normalize(v), glm::length(v));
      const glm::dvec3 end = c.origin_m + c.length_m * c.dir;
      EXPECT_NEAR(glm::length(end), R + h, 1e-6 * R) << d << " " << h;
      EXPECT_NEAR(std::acos(std::clamp(end.z / glm::length(end), -1.0, 1.0)), d / R, 1e-9) << d << " " << h;
      EXPECT_NEAR(std::atan2(end.y, end.x), 0.4, 1e-9) << d << " " << h;
      EXPECT_NEAR(glm::length(c.dir), 1.0, 1e-12);
      // Close by, the chord is the flat ray (they part by O(D/R)).
      if (d <= 1000.0) {
        EXPECT_LT(glm::length(c.dir - glm::normalize(v)), 1e-3);
      }
    }
  }
  // Beyond each other's horizon the chord passes below the ground; the air there is the ground's,
  // so the segment stays finite and dim.
  const glm::dvec3 far(2000000.0, 0.0, -eye);
  Quadrature q;
  q.view_steps = 64;
  Parameters once = p;
  once.multiple_scattering = false;
  const Segment s =
      aerialPerspectiveOfFlatPoint(once, eye, glm::normalize(far), glm::length(far), viewDir(10.0, 0.0), q);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(std::isfinite(s.inscattered[k]) && std::isfinite(s.transmittance[k]));
    EXPECT_LT(s.transmittance[k], 1e-3);
  }
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
  // A slanted segment, 6 km up down to the ground at 30°: T_sun changes along it. The closed form
  // takes the sunlight's path as plane-parallel, ℓ₀ − t·dir.z/μ_s, where the model's sun reads the
  // round planet's chord at each altitude (μ_s = 0.5 here): they part by O(Δh·(1 − μ_s²)/(R·μ_s³))
  // of the path, a few metres over these 6 km: measured ≤ 7.6·10⁻⁴ of L_in, bound 2·10⁻³.
  Quadrature fine;
  fine.view_steps = 2048;
  const glm::dvec3 down = viewDir(-30.0, 70.0);
  const glm::dvec3 high = observerAt(p, 6000.0);
  for (double d : {3000.0, 12000.0}) {
    const Segment s = integrateSegment(p, high, down, d, to_sun, fine, /*plane_parallel=*/true);
    const test::ClosedForm cf = test::homogeneousClosedForm(p, 6000.0, to_sun, down, d);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.transmittance[c], cf.transmittance[c], 1e-12) << "slanted, d " << d;
      EXPECT_NEAR(s.inscattered[c], cf.inscattered[c], 2e-3 * cf.inscattered[c]) << "slanted, d " << d;
      std::printf("slanted segment d %.0f m, channel %d: L_in %.3e off\n", d, c,
                  s.inscattered[c] / cf.inscattered[c] - 1.0);
    }
  }
}

// The flat view's grazing rays (issue 14, twelfth session): a plane-parallel ray down through the
// whole ozone layer (40 km → 10 km) takes the tent's mean β_O/2 over its path 2w/|μ|, capped at the
// round planet's longest chord through the layer, 2·√(2R·2w): T = e^{−β_O/2·min(2w/|μ|, chord)}.
// Rayleigh and Mie off, so the ozone alone is left; 4096 midpoint pieces on a piecewise-linear tent.
TEST(AtmosphereModel, PlaneParallelOzonePathIsCappedAtTheRoundPlanetsChord) {
  Parameters p = Parameters::earth();
  p.rayleigh_scattering_per_m = glm::dvec3(0.0);
  p.mie_scattering_per_m = p.mie_absorption_per_m = glm::dvec3(0.0);
  p.multiple_scattering = false;
  Quadrature q;
  q.view_steps = 4096;
  q.transmittance_steps = 8;
  const double layer_m = 2.0 * p.ozone_half_width_m;
  const double chord_m = 2.0 * std::sqrt(2.0 * p.bottom_radius_m * layer_m);
  EXPECT_NEAR(chord_m, 1.2365e6, 1e3);
  for (double mu : {-0.5, -0.03, -0.01, -0.001}) {
    const glm::dvec3 dir(std::sqrt(1.0 - mu * mu), 0.0, mu);
    const double top_m = p.ozone_center_m + p.ozone_half_width_m;
    const Segment s = integrateSegment(p, observerAt(p, top_m), dir, layer_m / -mu, viewDir(30.0, 0.0), q, true);
    const double path_m = std::min(layer_m / -mu, chord_m);
    EXPECT_DOUBLE_EQ(planeParallelOzoneCap(p, mu), path_m / (layer_m / -mu));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.transmittance[c], std::exp(-0.5 * p.ozone_absorption_per_m[c] * path_m), 1e-6) << "mu " << mu;
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

// Issue 14 (seventeenth session): is the low sun's colour right? The sunlight through a
// Rayleigh-only atmosphere (exponential, scale height H, β_R at 680/550/440 nm) against the
// closed-form Beer–Lambert law along the curved path: τ = β_R·H·e^{−h/H}·Ch(x, χ), x = (R + h)/H,
// with Chapman's grazing-incidence function in its asymptotic form (Chapman 1931; e.g. Schüler
// 2012, GPU Pro 3 "An approximation to the Chapman grazing-incidence function")
//   Ch(x, χ) ≈ √(πx/2) · e^{y²} · erfc(y),  y = √(x/2)·cos χ,
// whose own error is ≈ 1/x ≈ 0.13 % of τ for every χ ≤ 90° (x ≈ 800); the top at 100 km truncates
// e^{−12.5} of it. Tolerance 0.3 % of τ. And the air mass at 6° (zenith 84°) against Kasten and
// Young 1989's empirical formula for the real atmosphere (8.84, refraction included, which this
// model has not: 1.3 % apart; tolerance 2 %).
TEST(AtmosphereModel, LowSunThroughRayleighAirIsTheClosedFormBeerLambert) {
  Parameters p = Parameters::earth();
  p.mie_scattering_per_m = glm::dvec3(0.0);
  p.mie_absorption_per_m = glm::dvec3(0.0);
  p.ozone_absorption_per_m = glm::dvec3(0.0);
  const double H = p.rayleigh_scale_height_m;
  for (double h : {0.0, 2000.0, 5000.0, 10000.0}) {
    for (double elevation_deg : {90.0, 30.0, 10.0, 6.0, 3.0}) {
      const double mu = std::sin(elevation_deg * kPi / 180.0);
      const double x = (p.bottom_radius_m + h) / H, y = std::sqrt(x / 2.0) * mu;
      const double chapman = std::sqrt(kPi * x / 2.0) * std::exp(y * y) * std::erfc(y);
      const glm::dvec3 t = transmittanceToTop(p, p.bottom_radius_m + h, mu, 4096);
      for (int c = 0; c < 3; ++c) {
        const double tau_closed = p.rayleigh_scattering_per_m[c] * H * std::exp(-h / H) * chapman;
        EXPECT_NEAR(-std::log(t[c]) / tau_closed, 1.0, 3e-3)
            << "h " << h << " m, sun " << elevation_deg << " deg, channel " << c;
      }
    }
  }
  const double tau_6 = -std::log(transmittanceToTop(p, p.bottom_radius_m, std::sin(6.0 * kPi / 180.0), 4096).g);
  const double air_mass = tau_6 / (p.rayleigh_scattering_per_m.g * H);
  const double z = 84.0;  // Kasten & Young 1989: 1 / (cos z + 0.50572·(96.07995° − z)^−1.6364)
  const double kasten_young = 1.0 / (std::cos(z * kPi / 180.0) + 0.50572 * std::pow(96.07995 - z, -1.6364));
  EXPECT_NEAR(kasten_young, 8.84, 0.01);
  EXPECT_NEAR(air_mass / kasten_young, 1.0, 0.02);
}

// The full Earth model (Rayleigh, Mie, ozone) at a 6° sun: the direct beam at sea level is
// strongly reddened — (0.59, 0.30, 0.093): R e^{−0.046·8.7}, G e^{−0.108·8.7} and the ozone's
// Chappuis band in green, B e^{−0.265·8.7} — and it pales with height as the air mass above
// halves every 5.5 km (the closed forms of the test above, with the Mie and ozone paths of the
// same geometry: Python quadrature, 20 000 steps). At 8 km, where the storm's anvils stand, the
// sunlight is (0.80, 0.57, 0.42): peach, not orange. Values to 0.005.
TEST(AtmosphereModel, LowSunIsReddenedAtTheGroundAndPalerAtTheAnvils) {
  const Parameters p = Parameters::earth();
  const double mu = std::sin(6.0 * kPi / 180.0);
  const glm::dvec3 ground = sunTransmittance(p, p.bottom_radius_m, mu, 4096);
  const glm::dvec3 anvil = sunTransmittance(p, p.bottom_radius_m + 8000.0, mu, 4096);
  const glm::dvec3 ground_expected(0.590, 0.300, 0.093), anvil_expected(0.798, 0.565, 0.423);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(ground[c], ground_expected[c], 5e-3) << "channel " << c;
    EXPECT_NEAR(anvil[c], anvil_expected[c], 5e-3) << "channel " << c;
  }
  EXPECT_LT(ground.b / ground.r, 0.2);  // orange-red at the ground
  EXPECT_GT(anvil.b / anvil.r, 0.5);    // half the blue left at 8 km
}

// The ground under the clouds at a low sun (their light from below; render/raycast/
// cloud_renderer.cpp): horizontalIrradiance is the direct beam μ_s·T_sun — the closed form's colour
// above — plus the sky. At 6°, 1 km up, the ground is lit warm (R > G > B) although the sky's share
// is blue; the clear-sky model used before gave the bounce the unattenuated sun, (1, 1, 1)·μ_s plus a
// bluish sky: B/R 1.3. At noon the same meter reads nearly neutral. Its luminance is the exposure's
// meter (horizontalIlluminance).
TEST(AtmosphereModel, GroundUnderALowSunIsLitWarm) {
  const Parameters p = Parameters::earth();
  const double low = 6.0 * kPi / 180.0, noon = 60.0 * kPi / 180.0;
  const glm::dvec3 e = horizontalIrradiance(p, 1000.0, low);
  const glm::dvec3 direct = std::sin(low) * sunTransmittance(p, p.bottom_radius_m + 1000.0, std::sin(low), 4096);
  for (int c = 0; c < 3; ++c) EXPECT_GT(e[c], direct[c]) << c;  // the sky adds to the beam
  EXPECT_NEAR(direct.r, std::sin(low) * 0.637, 2e-3);           // the closed form's beam at 1 km (Python)
  EXPECT_GT(e.r, e.g);
  EXPECT_GT(e.g, e.b);
  EXPECT_LT(e.b / e.r, 0.8);
  const glm::dvec3 n = horizontalIrradiance(p, 1000.0, noon);
  EXPECT_GT(n.b / n.r, 0.8);
  EXPECT_NEAR(0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z, horizontalIlluminance(p, 1000.0, low), 1e-12);
  std::printf("ground at 1 km: sun 6 deg %.4f %.4f %.4f (direct %.4f %.4f %.4f), sun 60 deg %.4f %.4f %.4f\n", e.r, e.g,
              e.b, direct.r, direct.g, direct.b, n.r, n.g, n.b);
}

}  // namespace
}  // namespace nph::atmosphere
