#pragma once
// Sampling helpers of the path tracer (and of the Monte Carlo radiance volume, its twin in tallies).
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace nph::reference {

/// Unit vector at angle acos(cos_theta) from the unit vector `axis`, at azimuth `phi` [rad] in an
/// orthonormal basis around it (Duff et al. 2017, "Building an orthonormal basis, revisited":
/// branch-free and continuous except at axis.z = 0⁻/0⁺, exact for axis = ±z).
inline glm::dvec3 aroundAxis(const glm::dvec3& axis, double cos_theta, double phi) {
  const double sign = std::copysign(1.0, axis.z);
  const double a = -1.0 / (sign + axis.z);
  const double b = axis.x * axis.y * a;
  const glm::dvec3 t{1.0 + sign * axis.x * axis.x * a, sign * b, -sign * axis.x};
  const glm::dvec3 bt{b, sign + axis.y * axis.y * a, -axis.y};
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return glm::normalize(sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * bt + cos_theta * axis);
}

/// Russian roulette past a depth (reference/path_tracer.h): the probability that a path survives
/// its n-th collision (n ≥ the depth D). Its weight is divided by it, so after N collisions it is
/// (N + 1)/D — linear in the path's length, which keeps the estimator's variance finite.
/// (glsl/dlm/radiance_volume.comp spells the same schedule for the GPU photons.)
inline double rouletteSurvival(int collisions) { return double(collisions) / double(collisions + 1); }

}  // namespace nph::reference
