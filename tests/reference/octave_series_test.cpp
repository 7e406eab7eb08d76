// The multiple-scattering octave series (src/lighting/octave_series.h) against its definition:
// one octave is the eye pass's single-scattering term exactly, octave n uses the same DLM value
// raised to aⁿ (T(aⁿτ) = T(τ)^{aⁿ}), and the phase lobes flatten with cⁿ towards isotropic.
#include "lighting/octave_series.h"
#include "lighting/cloud_light.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "physics/phase.h"

namespace nph::reference {
namespace {
using lighting::OctaveSeries;
using lighting::octaveSunFactor;

TEST(OctaveSeries, OneOctaveIsSingleScatteringWithTheNesMix) {
  const OctaveSeries one{};
  for (double cosPsi : {-1.0, -0.3, 0.0, 0.5, 0.99, 1.0})
    for (double w : {0.0, 0.25, 1.0}) {
      const double pv =
          w * physics::henyeyGreenstein(cosPsi, 0.75) + (1.0 - w) * physics::henyeyGreenstein(cosPsi, 0.85);
      EXPECT_NEAR(octaveSunFactor(one, 0.37, cosPsi, w, 0.75, 0.85), 0.37 * pv, 1e-9 * pv)
          << "cos psi " << cosPsi << ", ice weight " << w;
    }
}

TEST(OctaveSeries, OctavesScaleOpticalDepthEnergyAndAnisotropy) {
  const OctaveSeries s{4, 0.3, 0.6, 0.5, {}};
  const double tau = 2.5, sunlight = std::exp(-tau), cosPsi = 0.2, w = 0.4;
  double expected = 0.0;
  for (int n = 0; n < 4; ++n) {
    const double g = std::pow(0.5, n);
    const double pv =
        w * physics::henyeyGreenstein(cosPsi, g * 0.75) + (1.0 - w) * physics::henyeyGreenstein(cosPsi, g * 0.85);
    expected += std::pow(0.6, n) * std::exp(-std::pow(0.3, n) * tau) * pv;
  }
  EXPECT_NEAR(octaveSunFactor(s, sunlight, cosPsi, w, 0.75, 0.85), expected, 1e-12 * expected);
  // No sunlight at all: every octave is 0 (0^{aⁿ} = 0, no NaN from log 0).
  EXPECT_EQ(octaveSunFactor(s, 0.0, cosPsi, w, 0.75, 0.85), 0.0);
  // Full sunlight, isotropic octaves (c = 0 from n = 1): Σ bⁿ with the first lobe forward.
  const OctaveSeries flat{3, 0.5, 0.5, 0.0, {}};
  EXPECT_NEAR(octaveSunFactor(flat, 1.0, cosPsi, 0.0, 0.75, 0.85),
              physics::henyeyGreenstein(cosPsi, 0.85) + (0.5 + 0.25) / (4.0 * std::numbers::pi), 1e-12);
}

TEST(OctaveSeries, FreeWeightsReplaceTheGeometricEnergies) {
  // Free weights (1, b, b²) are the geometric series exactly; the GLSL twin (octaveSeries) agrees.
  const OctaveSeries geometric{3, 0.4, 0.6, 0.3, {}};
  const OctaveSeries free{3, 0.4, 0.6, 0.3, {1.0, 0.6, 0.36}};
  for (double sunlight : {0.0, 0.05, 0.7, 1.0}) {
    const double f = octaveSunFactor(geometric, sunlight, 0.3, 0.2, 0.75, 0.85);
    EXPECT_NEAR(octaveSunFactor(free, sunlight, 0.3, 0.2, 0.75, 0.85), f, 1e-12);
    EXPECT_NEAR(lighting::octaveSeries(sunlight, 0.3, 0.2, 0.75, 0.85, geometric), f, 1e-12);
  }
}

TEST(OctaveSeries, MoreOctavesNeverDarken) {
  for (double sunlight : {0.0, 1e-6, 0.01, 0.5, 1.0}) {
    double previous = -1.0;
    for (int n = 1; n <= 12; ++n) {
      const double f = octaveSunFactor(OctaveSeries{n, 0.2, 0.7, 0.6, {}}, sunlight, -0.5, 0.3, 0.75, 0.85);
      EXPECT_TRUE(std::isfinite(f));
      EXPECT_GE(f, previous) << n << " octaves, sunlight " << sunlight;
      previous = f;
    }
  }
}

}  // namespace
}  // namespace nph::reference
