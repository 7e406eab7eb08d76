#include "physics/pchip.h"

#include <cmath>

namespace nph::physics {

namespace {

double endSlope(double h0, double h1, double del0, double del1) {
  double d = ((2.0 * h0 + h1) * del0 - h0 * del1) / (h0 + h1);
  if (std::signbit(d) != std::signbit(del0) || del0 == 0.0) {
    d = 0.0;
  } else if (std::signbit(del0) != std::signbit(del1) && std::abs(d) > 3.0 * std::abs(del0)) {
    d = 3.0 * del0;
  }
  return d;
}

}  // namespace

void pchipSlopes(std::span<const double> x, std::span<const double> y, std::span<double> d) {
  const std::size_t n = x.size();
  if (n == 0) return;
  if (n == 1) {
    d[0] = 0.0;
    return;
  }
  auto h = [&](std::size_t k) { return x[k + 1] - x[k]; };
  auto del = [&](std::size_t k) { return (y[k + 1] - y[k]) / h(k); };
  if (n == 2) {
    d[0] = d[1] = del(0);
    return;
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double a = del(k - 1), b = del(k);
    if (a == 0.0 || b == 0.0 || std::signbit(a) != std::signbit(b)) {
      d[k] = 0.0;
    } else {
      const double w1 = 2.0 * h(k) + h(k - 1);
      const double w2 = h(k) + 2.0 * h(k - 1);
      d[k] = (w1 + w2) / (w1 / a + w2 / b);
    }
  }
  d[0] = endSlope(h(0), h(1), del(0), del(1));
  d[n - 1] = endSlope(h(n - 2), h(n - 3), del(n - 2), del(n - 3));
}

double pchipEvaluate(std::span<const double> x, std::span<const double> y, std::span<const double> d, std::size_t k,
                     double xq) {
  if (x.size() == 1) return y[0];
  const double hk = x[k + 1] - x[k];
  const double t = (xq - x[k]) / hk;
  const double t2 = t * t, t3 = t2 * t;
  // cubic Hermite basis
  const double h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
  const double h10 = t3 - 2.0 * t2 + t;
  const double h01 = -2.0 * t3 + 3.0 * t2;
  const double h11 = t3 - t2;
  return h00 * y[k] + h10 * hk * d[k] + h01 * y[k + 1] + h11 * hk * d[k + 1];
}

}  // namespace nph::physics
