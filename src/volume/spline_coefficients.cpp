#include "volume/spline_coefficients.h"

#include <tbb/parallel_for.h>

namespace nph::volume {
namespace {

/// The Thomas algorithm's forward factors of the n × n system tridiag(1, 4, 1)/6 (the same for
/// every line of an axis): m[i] = 1 / (4 − m[i−1]) scaled, as in Press et al., Numerical Recipes §2.4.
std::vector<double> forwardFactors(int n) {
  std::vector<double> gamma(static_cast<std::size_t>(n));
  double beta = 4.0;
  gamma[0] = 0.0;
  for (int i = 1; i < n; ++i) {
    gamma[std::size_t(i)] = 1.0 / beta;
    beta = 4.0 - gamma[std::size_t(i)];
  }
  return gamma;
}

/// Solves one line of `a` (n values, `stride` apart, from `base`) in place, in double.
void solveLine(std::vector<float>& a, std::size_t base, std::size_t stride, int n, const std::vector<double>& gamma,
               std::vector<double>& u) {
  // (c[i−1] + 4c[i] + c[i+1]) = 6 s[i]: forward elimination, back substitution.
  double beta = 4.0;
  u[0] = 6.0 * double(a[base]) / beta;
  for (int i = 1; i < n; ++i) {
    beta = 4.0 - gamma[std::size_t(i)];
    u[std::size_t(i)] = (6.0 * double(a[base + std::size_t(i) * stride]) - u[std::size_t(i - 1)]) / beta;
  }
  for (int i = n - 2; i >= 0; --i) u[std::size_t(i)] -= gamma[std::size_t(i + 1)] * u[std::size_t(i + 1)];
  for (int i = 0; i < n; ++i) a[base + std::size_t(i) * stride] = float(u[std::size_t(i)]);
}

}  // namespace

void interpolatingSplineCoefficients(std::vector<float>& a, int nx, int ny, int nz) {
  if (a.empty()) return;
  const int dims[3] = {nx, ny, nz};
  const std::size_t layer = std::size_t(nx) * std::size_t(ny);
  for (int axis = 0; axis < 3; ++axis) {
    const int n = dims[axis];
    if (n < 2) continue;
    const std::vector<double> gamma = forwardFactors(n);
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? std::size_t(nx) : layer;
    const std::size_t lines = std::size_t(nx) * std::size_t(ny) * std::size_t(nz) / std::size_t(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lines), [&](const tbb::blocked_range<std::size_t>& r) {
      std::vector<double> u(static_cast<std::size_t>(n));
      for (std::size_t l = r.begin(); l != r.end(); ++l) {
        std::size_t base = 0;
        if (axis == 0) base = l * std::size_t(nx);
        else if (axis == 1) base = (l / std::size_t(nx)) * layer + l % std::size_t(nx);
        else base = l;
        solveLine(a, base, stride, n, gamma, u);
      }
    });
  }
}

ExtinctionVolumes splineCoefficientVolumes(const ExtinctionVolumes& volumes) {
  ExtinctionVolumes c = volumes;
  interpolatingSplineCoefficients(c.ice_per_m, c.nx, c.ny, c.nz);
  interpolatingSplineCoefficients(c.water_per_m, c.nx, c.ny, c.nz);
  c.updateMaxima();
  return c;
}

}  // namespace nph::volume
