#include "physics/effective_radius.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "physics/constants.h"

namespace nph::physics {

double cubeRootPositive(double x) {
  // Within 2^±1000 (λ³ of any particle lies within 1e3 … 1e30 m⁻³): beyond, the guess is no guess
  // (0, subnormals, negative, Inf, NaN) or 2y³ overflows.
  if (!(x >= 0x1.0p-1000 && x <= 0x1.0p1000)) return std::cbrt(x);
  // The exponent divided by 3 (Kahan's bit trick; the constant puts the bias back, 1 023·2/3 in the
  // exponent field, tuned for the smallest worst-case error of the guess).
  const auto bits = std::bit_cast<std::uint64_t>(x);
  double y = std::bit_cast<double>(bits / 3 + 0x2A9F7893782DA1CEull);
  for (int i = 0; i < 2; ++i) {  // Halley, the ratio first: y·(y³ + 2x) alone underflows near 2⁻¹⁰⁰⁰
    const double y3 = y * y * y;
    y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
  }
  // Newton, as a small correction to y: its own rounding is a third of an ulp, so y ends within
  // an ulp of the true root.
  y -= (y * y * y - x) / (3.0 * y * y);
  return y;
}

double effectiveRadiusFromNumber(double q, double n, double rho_p, double mu, double fallback_m, double min_m,
                                 double max_m) {
  if (!(q > 0.0) || !(n > 0.0) || !std::isfinite(q) || !std::isfinite(n)) return fallback_m;
  const double lambda_cubed = (kPi / 6.0) * rho_p * (n / q) * (mu + 1.0) * (mu + 2.0) * (mu + 3.0);
  const double lambda_per_m = cubeRootPositive(lambda_cubed);
  return std::clamp((mu + 3.0) / (2.0 * lambda_per_m), min_m, max_m);
}

}  // namespace nph::physics
