#pragma once
// A homogeneous test atmosphere and the closed form of its aerial perspective (issue 14 "Done
// means": a ground pixel at distance d gets L0·e^{−σ_t d} + L_in). Shared by the CPU model's test,
// the GPU probe's and the rendered frame's (tests/render/raycast_gl_test.cpp).
#include <cmath>

#include "atmosphere/atmosphere.h"

namespace nph::atmosphere::test {

/// A 10 km layer of constant density (scale heights 10¹⁵ km), no ozone, single scattering only:
/// σ_s = (2, 3, 5)·10⁻⁵ /m Rayleigh plus 10⁻⁵ /m Mie (absorbing 0.2·10⁻⁵ /m).
inline Parameters homogeneousAtmosphere() {
  Parameters p;
  p.top_radius_m = p.bottom_radius_m + 10000.0;
  p.rayleigh_scattering_per_m = {2e-5, 3e-5, 5e-5};
  p.rayleigh_scale_height_m = 1e18;
  p.mie_scattering_per_m = glm::dvec3(1e-5);
  p.mie_absorption_per_m = glm::dvec3(0.2e-5);
  p.mie_scale_height_m = 1e18;
  p.ozone_absorption_per_m = glm::dvec3(0.0);
  p.multiple_scattering = false;
  return p;
}

struct ClosedForm {
  glm::dvec3 transmittance, inscattered;
};

/// A segment of length d from altitude h along unit `dir`, plane-parallel (the flat view's air:
/// altitude h + t·dir.z, the sun's zenith cosine μ_s = to_sun.z everywhere). The sunlight reaching
/// the point at t has crossed ℓ(t) = ℓ₀ − t·dir.z/μ_s of air (ℓ₀ the chord from R + h to the top
/// sphere along μ_s; the plane-parallel slope, which the round planet's chord follows to
/// O(Δh·(1 − μ_s²)/(R·μ_s³))), so with k = 1 − dir.z/μ_s:
///   T = e^{−σ_t d},  L_in = (σ_R p_R + σ_M p_M)·e^{−σ_t ℓ₀}·(1 − e^{−σ_t k d})/(σ_t k).
/// A horizontal segment (k = 1) has every point ℓ₀ from the top: L_in = σ_s p/σ_t·T_sun·(1 − T).
inline ClosedForm homogeneousClosedForm(const Parameters& p, double altitude_m, const glm::dvec3& to_sun,
                                        const glm::dvec3& dir, double d) {
  const Medium m = mediumAt(p, altitude_m);
  const double c = glm::dot(dir, to_sun);
  const double path = distanceToTop(p, p.bottom_radius_m + altitude_m, to_sun.z);
  const double k = 1.0 - dir.z / to_sun.z;
  ClosedForm out{};
  for (int i = 0; i < 3; ++i) {
    const double sigma = m.extinction_per_m[i];
    const double sun = std::exp(-sigma * path);
    out.transmittance[i] = std::exp(-sigma * d);
    out.inscattered[i] =
        (m.rayleigh_scattering_per_m[i] * rayleighPhase(c) + m.mie_scattering_per_m[i] * miePhase(c, p.mie_g)) * sun *
        (1.0 - std::exp(-sigma * k * d)) / (sigma * k);
  }
  return out;
}

}  // namespace nph::atmosphere::test
