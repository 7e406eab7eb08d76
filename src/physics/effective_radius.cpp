#include "physics/effective_radius.h"

#include <algorithm>
#include <cmath>

#include "physics/constants.h"

namespace nph::physics {

double effectiveRadiusFromNumber(double q, double n, double rho_p, double mu, double fallback_m, double min_m,
                                 double max_m) {
  if (!(q > 0.0) || !(n > 0.0) || !std::isfinite(q) || !std::isfinite(n)) return fallback_m;
  const double lambda_cubed = (kPi / 6.0) * rho_p * (n / q) * (mu + 1.0) * (mu + 2.0) * (mu + 3.0);
  const double lambda_per_m = std::cbrt(lambda_cubed);
  return std::clamp((mu + 3.0) / (2.0 * lambda_per_m), min_m, max_m);
}

}  // namespace nph::physics
