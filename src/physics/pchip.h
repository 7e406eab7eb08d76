#pragma once
// Monotone piecewise cubic Hermite interpolation (PCHIP; Fritsch & Carlson 1980, SIAM J. Numer.
// Anal. 17; slopes of Fritsch & Butland 1984), as Muth 2026 §3.3.1 uses for the vertical
// resampling of model levels: no overshoot in steep vertical gradients, so non-negative data
// stay non-negative and a cloud edge does not ring.
//
// Nodes x_0 < x_1 < ... < x_{n-1}, values y_k, secants δ_k = (y_{k+1} - y_k) / h_k, h_k = x_{k+1}-x_k.
// Interior slopes: d_k = 0 where δ_{k-1} and δ_k differ in sign or one is 0, else the weighted
// harmonic mean (w1 + w2) / (w1/δ_{k-1} + w2/δ_k), w1 = 2h_k + h_{k-1}, w2 = h_k + 2h_{k-1},
// which satisfies the Fritsch-Carlson monotonicity region (α, β <= 3).
// End slopes: the non-centred three-point formula, set to 0 when its sign differs from δ, and
// limited to 3δ when the secants change sign (as SciPy's PchipInterpolator and MATLAB's pchip).
// Each interval then is the cubic Hermite polynomial with values y_k, y_{k+1} and slopes d_k,
// d_{k+1}: monotone between its nodes, exact on linear data (all d_k = δ).
#include <cstddef>
#include <span>

namespace nph::physics {

/// Computes PCHIP slopes d (size n) for nodes x (strictly increasing) and values y (size n).
/// n = 1: d = 0. n = 2: d = δ (linear).
void pchipSlopes(std::span<const double> x, std::span<const double> y, std::span<double> d);

/// Evaluates the interpolant on interval [x_k, x_{k+1}] at xq.
double pchipEvaluate(std::span<const double> x, std::span<const double> y, std::span<const double> d, std::size_t k,
                     double xq);

}  // namespace nph::physics
