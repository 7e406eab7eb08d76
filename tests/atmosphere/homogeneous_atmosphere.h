#pragma once
// A homogeneous test atmosphere and the closed form of its aerial perspective (issue 14 "Done
// means": a ground pixel at distance d gets L0·e^{−σ_t d} + L_in·(1 − e^{−σ_t d})). Shared by the
// CPU model's test and the GPU test.
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

/// A horizontal segment of length d at altitude h, plane-parallel, so that the sun's path is the
/// same from every point of it (T_sun = e^{−σ_t·ℓ}, ℓ the chord from R + h to the top sphere): T = e^{−σ_t d}, L_in =
/// (σ_R p_R + σ_M p_M)/σ_t · T_sun · (1 − T).
inline ClosedForm homogeneousClosedForm(const Parameters& p, double altitude_m, const glm::dvec3& to_sun,
                                        const glm::dvec3& dir, double d) {
  const Medium m = mediumAt(p, altitude_m);
  const double c = glm::dot(dir, to_sun);
  const double path = distanceToTop(p, p.bottom_radius_m + altitude_m, to_sun.z);
  ClosedForm out{};
  for (int k = 0; k < 3; ++k) {
    const double sigma = m.extinction_per_m[k];
    const double sun = std::exp(-sigma * path);
    out.transmittance[k] = std::exp(-sigma * d);
    out.inscattered[k] =
        (m.rayleigh_scattering_per_m[k] * rayleighPhase(c) + m.mie_scattering_per_m[k] * miePhase(c, p.mie_g)) / sigma *
        sun * (1.0 - out.transmittance[k]);
  }
  return out;
}

}  // namespace nph::atmosphere::test
